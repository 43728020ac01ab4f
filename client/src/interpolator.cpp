#include "jetrace/client/interpolator.hpp"

#include <algorithm>

namespace jetrace::client {

void Interpolator::set_rates(int tick_rate_hz, int snapshot_rate_hz) {
    ticks_per_snapshot_ = static_cast<double>(tick_rate_hz) / std::max(1, snapshot_rate_hz);
}

Vec3 Interpolator::other(const SnapshotStore& store, int slot, std::uint64_t now_us, double period_us) const {
    const auto s = static_cast<std::size_t>(slot);
    const WorldState& latest = store.latest().state;
    if (s >= latest.cars.size() || store.newest_tick() == proto::kNoTick) return Vec3::Zero();
    // The render tick trails the newest snapshot by the interpolation delay,
    // advancing with the client's clock between snapshots.
    const double since = static_cast<double>(now_us - store.latest_at_us()) / period_us;
    const double render = store.newest_tick() + since - delay_snapshots_ * ticks_per_snapshot_;
    // The two stored snapshots around the render tick.
    const SnapshotStore::Entry* a = nullptr;
    const SnapshotStore::Entry* b = nullptr;
    for (const SnapshotStore::Entry& e : store.entries()) {
        if (e.tick == proto::kNoTick || s >= e.world.state.cars.size() || !e.world.state.cars[s].active) continue;
        if (e.tick <= render && (!a || e.tick > a->tick)) a = &e;
        if (e.tick > render && (!b || e.tick < b->tick)) b = &e;
    }
    if (a && b) {
        const double f = (render - a->tick) / static_cast<double>(b->tick - a->tick);
        const Vec3& pa = a->world.state.cars[s].position;
        return pa + (b->world.state.cars[s].position - pa) * f;
    }
    if (a) return a->world.state.cars[s].position;  // never extrapolate
    if (b) return b->world.state.cars[s].position;
    return latest.cars[s].position;
}

}  // namespace jetrace::client
