// jetrace-server's replay of each race (--record, --sign-key): a
// RaceObserver that writes one file per race with replay::Writer. A write
// that fails is logged once per race, counted, and stops that race's
// recording; the race goes on.
#pragma once

#include "jetrace/replay/signature.hpp"
#include "jetrace/replay/writer.hpp"
#include "jetrace/server/race_observer.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace jetrace::server {

struct RecorderConfig {
    /// Where each race's replay goes; %n and %t expand as in expand_path()
    /// (server/include/jetrace/server/path_template.hpp).
    std::string path_template;
    /// Signs each replay with this Ed25519 secret key (unset = unsigned).
    std::optional<replay::SigningKey> sign_key;
};

class ReplayRecorder final : public RaceObserver {
public:
    explicit ReplayRecorder(RecorderConfig config) : config_(std::move(config)) {}

    void race_started(const replay::Header& header) override;
    void before_step(std::uint32_t tick, std::span<const std::uint8_t> removed, std::span<const Input> inputs) override;
    void after_step(const WorldState& after) override;
    void race_ended(const replay::Trailer& trailer) override;
    void stopped() override;

    /// Replays whose writing failed (each logged with what was lost).
    std::uint32_t failures() const { return failures_; }
    /// Bytes handed to the OS, every race's replay so far.
    std::uint64_t bytes_written() const { return bytes_before_ + writer_.bytes_written(); }

private:
    void check();

    RecorderConfig config_;
    replay::Writer writer_;
    std::uint32_t race_number_ = 0;
    std::uint32_t failures_ = 0;
    bool failure_logged_ = false;
    /// Replay bytes of the races before the one writer_ holds.
    std::uint64_t bytes_before_ = 0;
};

}  // namespace jetrace::server
