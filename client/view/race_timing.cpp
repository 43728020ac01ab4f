#include "race_timing.hpp"

#include <algorithm>

namespace jetrace::view {

void RaceTiming::start(const WorldState& initial, int gates) {
    gates_ = std::max(gates, 1);
    last_.clear();
    for (const CarState& c : initial.cars) last_.push_back({c.lap, c.next_checkpoint, c.finished});
    pass_ticks_.assign(initial.cars.size(), {});
}

void RaceTiming::after_step(const WorldState& state) {
    for (std::size_t s = 0; s < state.cars.size() && s < last_.size(); ++s) {
        const CarState& c = state.cars[s];
        const Progress now{c.lap, c.next_checkpoint, c.finished};
        // A step passes at most one gate per car (apply_race_rules tests one).
        if (c.active && now != last_[s]) pass_ticks_[s].push_back(state.tick);
        last_[s] = now;
    }
}

std::size_t RaceTiming::passes(int slot, std::uint32_t tick) const {
    if (slot < 0 || static_cast<std::size_t>(slot) >= pass_ticks_.size()) return 0;
    const auto& p = pass_ticks_[static_cast<std::size_t>(slot)];
    return static_cast<std::size_t>(std::upper_bound(p.begin(), p.end(), tick) - p.begin());
}

std::optional<double> RaceTiming::best_lap_s(int slot, std::uint32_t tick, int tick_rate_hz) const {
    const std::size_t n = passes(slot, tick);
    if (n == 0) return std::nullopt;
    const auto& p = pass_ticks_[static_cast<std::size_t>(slot)];
    const auto g = static_cast<std::size_t>(gates_);
    // Pass 0 is the first crossing of the start line; lap k ends at pass k * gates.
    std::optional<std::uint32_t> best;
    for (std::size_t end = g; end < n; end += g) {
        const std::uint32_t lap = p[end] - p[end - g];
        if (!best || lap < *best) best = lap;
    }
    if (!best) return std::nullopt;
    return static_cast<double>(*best) / tick_rate_hz;
}

std::optional<double> RaceTiming::gap_s(int slot, int leader, std::uint32_t tick, int tick_rate_hz) const {
    if (slot == leader) return std::nullopt;
    const std::size_t n = passes(slot, tick);
    if (n == 0 || passes(leader, tick) < n) return std::nullopt;
    const std::uint32_t mine = pass_ticks_[static_cast<std::size_t>(slot)][n - 1];
    const std::uint32_t theirs = pass_ticks_[static_cast<std::size_t>(leader)][n - 1];
    return (static_cast<double>(mine) - static_cast<double>(theirs)) / tick_rate_hz;
}

}  // namespace jetrace::view
