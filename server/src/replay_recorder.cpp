// ReplayRecorder: one replay file per race.
#include "jetrace/server/replay_recorder.hpp"

#include "jetrace/server/path_template.hpp"

#include <spdlog/spdlog.h>

namespace jetrace::server {

void ReplayRecorder::race_started(const replay::Header& header) {
    if (writer_.is_open()) writer_.abandon();  // a race that never ended
    race_number_ = header.race_number;
    failure_logged_ = false;
    bytes_before_ += writer_.bytes_written();  // the previous race's replay
    const std::string path = expand_path(config_.path_template, header.race_number, header.start_unix_s);
    if (!writer_.open(path, header, config_.sign_key)) check();
}

void ReplayRecorder::before_step(std::uint32_t tick, std::span<const std::uint8_t> removed,
                                 std::span<const Input> inputs) {
    writer_.record_tick(tick, removed, inputs);
}

void ReplayRecorder::after_step(const WorldState& after) {
    writer_.stepped(after);
    check();
}

void ReplayRecorder::race_ended(const replay::Trailer& trailer) {
    if (writer_.is_open()) writer_.finish(trailer);
    check();
}

void ReplayRecorder::stopped() { writer_.abandon(); }

void ReplayRecorder::check() {
    if (writer_.error().empty() || failure_logged_) return;
    failure_logged_ = true;
    ++failures_;
    spdlog::error("race {}: {}", race_number_, writer_.error());
}

}  // namespace jetrace::server
