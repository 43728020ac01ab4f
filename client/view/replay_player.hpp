// A replay loaded for viewing: the file is read once (untrusted bytes,
// through jetrace::replay's Scanner) and re-simulated with the shared core,
// every recorded checkpoint checked against the re-simulated world; the
// inputs and a state every keep_every_ticks are kept, so that any tick is
// reached by stepping at most that many ticks from a kept state. What a
// seek shows is therefore bit for bit the world the recorder simulated.
#pragma once

#include "race_timing.hpp"

#include "jetrace/replay/format.hpp"
#include "jetrace/replay/verify.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace jetrace::view {

struct PlayerLimits {
    /// Largest replay file opened (unit: bytes): every input stays in memory.
    std::uint64_t max_file_bytes = std::uint64_t{256} << 20;
    /// A state is kept every this many ticks (unit: ticks, at least 1).
    std::uint32_t keep_every_ticks = 240;
};

class ReplayPlayer {
public:
    /// Reads and re-simulates `path`. False with a reason if it cannot be
    /// read, names an unknown track or other physics, or the re-simulated
    /// world differs from a recorded checkpoint. A replay that ends early
    /// (incomplete or truncated) is kept up to its last whole tick, with
    /// warning() saying so.
    bool load(const std::string& path, replay::SceneFor scenes, const PlayerLimits& limits, std::string& error);

    const Scene& scene() const { return *scene_; }
    const replay::Header& header() const { return header_; }
    const std::string& path() const { return path_; }
    const std::string& warning() const { return warning_; }
    bool complete() const { return complete_; }
    const replay::Trailer& trailer() const { return trailer_; }
    const RaceTiming& timing() const { return timing_; }
    std::uint32_t first_tick() const { return header_.initial.tick; }
    std::uint32_t last_tick() const { return first_tick() + static_cast<std::uint32_t>(ticks_); }
    std::uint32_t start_tick() const { return header_.initial.start_tick; }
    /// The world at `tick` (clamped to [first_tick, last_tick]) in `s`:
    /// stepped on from `s` when it is at most keep_every_ticks behind, else
    /// from the kept state at or before `tick`.
    void seek(WorldState& s, StepScratch& scratch, std::uint32_t tick) const;
    /// Ticks stepped by seeks so far (a figure of the benchmark).
    std::uint64_t steps_taken() const { return steps_taken_; }

private:
    bool read(replay::ByteSource& src, std::string& error);
    bool on_header(const replay::Event& ev, std::string& error);
    void on_tick(const replay::TickRecord& t, WorldState& s, StepScratch& scratch);
    bool on_checkpoint(const replay::Checkpoint& c, const WorldState& s, std::string& error) const;
    void step_one(WorldState& s, StepScratch& scratch) const;

    std::string path_;
    replay::SceneFor scenes_;
    const Scene* scene_ = nullptr;
    PlayerLimits limits_;
    replay::Header header_;
    replay::Trailer trailer_;
    bool complete_ = false;
    std::string warning_;
    std::size_t ticks_ = 0;
    std::size_t slots_ = 0;
    /// slots_ inputs per tick, tick after tick.
    std::vector<Input> inputs_;
    /// Slots removed before a tick, by tick index (rare).
    std::map<std::size_t, std::vector<std::uint8_t>> removed_;
    /// kept_[i] is the world at first_tick() + i * keep_every_ticks.
    std::vector<WorldState> kept_;
    RaceTiming timing_;
    mutable std::uint64_t steps_taken_ = 0;
};

}  // namespace jetrace::view
