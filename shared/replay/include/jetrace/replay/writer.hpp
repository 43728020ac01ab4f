// Writes a replay as the race runs: the header at the start, a tick record
// before every step, a checkpoint (and every keyframe_every ticks a
// keyframe) after the steps the header says, and at the end the trailer and,
// with a signing key, the signature. Records are buffered and flushed to the
// OS once a second of ticks; every write is checked, and the first failure
// stops the recording and is kept in error().
#pragma once

#include "jetrace/ai/offline_race.hpp"
#include "jetrace/replay/format.hpp"
#include "jetrace/replay/signature.hpp"

#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace jetrace::replay {

class Writer {
public:
    Writer() = default;
    ~Writer();
    Writer(const Writer&) = delete;
    Writer& operator=(const Writer&) = delete;

    /// Creates (truncates) `path` and writes the header. With `sign_key`,
    /// finish() signs the file. False and error() on failure.
    bool open(const std::string& path, const Header& header, const std::optional<SigningKey>& sign_key = std::nullopt);
    /// Before stepping tick `tick`: the cars removed before it and the inputs.
    void record_tick(std::uint32_t tick, std::span<const std::uint8_t> removed, std::span<const Input> inputs);
    /// After the step: writes the checkpoint and keyframe due at `state.tick`.
    void stepped(const WorldState& state);
    /// Writes the trailer (and signature), flushes, syncs to disk and closes.
    /// False (and error()) if any write of this replay failed.
    bool finish(const Trailer& trailer);
    /// Closes without a trailer: the file reads as incomplete.
    void abandon();

    bool is_open() const { return file_ != nullptr; }
    /// The first failure ("" if none).
    const std::string& error() const { return error_; }
    /// Bytes handed to the OS so far.
    std::uint64_t bytes_written() const { return written_; }

private:
    void put(RecordKind kind);
    void flush();
    void close();

    std::FILE* file_ = nullptr;
    std::string path_;
    std::string error_;
    std::vector<std::uint8_t> buffer_, payload_;
    std::optional<SigningKey> sign_key_;
    std::optional<SignatureStream> signed_;
    std::uint64_t written_ = 0;
    std::uint32_t initial_tick_ = 0;
    std::uint16_t checkpoint_every_ = 120;
    std::uint16_t keyframe_every_ = 600;
    int since_flush_ = 0;
};

/// Records an offline race (run_ai()) into a writer.
class Recorder final : public StepObserver {
public:
    explicit Recorder(Writer& w) : writer_(&w) {}
    void before_step(const WorldState& state, std::span<const Input> inputs) override {
        writer_->record_tick(state.tick, {}, inputs);
    }
    void after_step(const WorldState& state) override { writer_->stepped(state); }

private:
    Writer* writer_;
};

}  // namespace jetrace::replay
