// One page's playback of a replay and its ghosts: the tick it shows,
// whether it plays and how fast. Each page has its own; the replays
// themselves (inputs, kept states) are shared and read-only.
#pragma once

#include "replay_player.hpp"

#include <cstdint>
#include <vector>

namespace jetrace::view {

class Playback {
public:
    Playback(const ReplayPlayer& main, std::vector<const ReplayPlayer*> ghosts);

    /// Shows `tick` (clamped to the replay's ticks).
    void seek(std::uint32_t tick);
    void set_playing(bool playing);
    /// (unit: times real time; the caller checked the range).
    void set_speed(double speed) { speed_ = speed; }
    /// Moves on by `real_s` seconds of real time at the current speed when
    /// playing; stops at the last tick. True if the tick changed.
    bool advance(double real_s);

    std::uint32_t tick() const { return main_state_.tick; }
    bool playing() const { return playing_; }
    double speed() const { return speed_; }
    const ReplayPlayer& main() const { return *main_; }
    const WorldState& main_state() const { return main_state_; }
    std::size_t ghost_count() const { return ghosts_.size(); }
    const ReplayPlayer& ghost(std::size_t i) const { return *ghosts_[i]; }
    const WorldState& ghost_state(std::size_t i) const { return ghost_states_[i]; }

private:
    void sync_ghosts();

    const ReplayPlayer* main_;
    std::vector<const ReplayPlayer*> ghosts_;
    WorldState main_state_;
    StepScratch main_scratch_;
    std::vector<WorldState> ghost_states_;
    std::vector<StepScratch> ghost_scratch_;
    bool playing_ = false;
    double speed_ = 1.0;
    /// Ticks owed by real time but not yet stepped (unit: ticks, < 1).
    double carry_ticks_ = 0;
};

/// The tick of `ghost` at the race time `main` shows at `tick`: the same
/// number of ticks since each race's start, clamped to the ghost's ticks.
std::uint32_t ghost_tick(const ReplayPlayer& main, std::uint32_t tick, const ReplayPlayer& ghost);

}  // namespace jetrace::view
