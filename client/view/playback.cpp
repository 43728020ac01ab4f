#include "playback.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace::view {

std::uint32_t ghost_tick(const ReplayPlayer& main, std::uint32_t tick, const ReplayPlayer& ghost) {
    const std::int64_t race = static_cast<std::int64_t>(tick) - main.start_tick();
    const std::int64_t t = static_cast<std::int64_t>(ghost.start_tick()) + race;
    return static_cast<std::uint32_t>(std::clamp<std::int64_t>(t, ghost.first_tick(), ghost.last_tick()));
}

Playback::Playback(const ReplayPlayer& main, std::vector<const ReplayPlayer*> ghosts)
    : main_(&main), ghosts_(std::move(ghosts)), ghost_states_(ghosts_.size()), ghost_scratch_(ghosts_.size()) {
    seek(main.first_tick());
}

void Playback::seek(std::uint32_t tick) {
    main_->seek(main_state_, main_scratch_, tick);
    carry_ticks_ = 0;
    sync_ghosts();
}

void Playback::set_playing(bool playing) {
    playing_ = playing && tick() < main_->last_tick();
    carry_ticks_ = 0;
}

bool Playback::advance(double real_s) {
    if (!playing_) return false;
    carry_ticks_ += real_s * speed_ * main_->scene().physics.tick_rate_hz;
    const double whole = std::floor(carry_ticks_);
    if (whole < 1) return false;
    carry_ticks_ -= whole;
    const double room = static_cast<double>(main_->last_tick() - tick());
    const auto n = static_cast<std::uint32_t>(std::min(whole, room));
    main_->seek(main_state_, main_scratch_, tick() + n);
    sync_ghosts();
    if (tick() >= main_->last_tick()) playing_ = false;
    return n > 0;
}

void Playback::sync_ghosts() {
    for (std::size_t i = 0; i < ghosts_.size(); ++i) {
        ghosts_[i]->seek(ghost_states_[i], ghost_scratch_[i], ghost_tick(*main_, tick(), *ghosts_[i]));
    }
}

}  // namespace jetrace::view
