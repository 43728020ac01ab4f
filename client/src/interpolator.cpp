#include "jetrace/client/interpolator.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace::client {

namespace {

/// The stored snapshots of this race in which car `s` is active, newest at
/// or before `render` (a) and oldest after it (b); either may be null.
void bracket(const SnapshotStore& store, std::size_t s, double render, const SnapshotStore::Entry*& a,
             const SnapshotStore::Entry*& b) {
    a = nullptr;
    b = nullptr;
    for (const SnapshotStore::Entry& e : store.entries()) {
        if (e.tick == proto::kNoTick || s >= e.world.state.cars.size() || !e.world.state.cars[s].active) continue;
        if (e.tick <= render && (!a || e.tick > a->tick)) a = &e;
        if (e.tick > render && (!b || e.tick < b->tick)) b = &e;
    }
}

double fraction(const SnapshotStore::Entry& a, const SnapshotStore::Entry& b, double render) {
    return (render - a.tick) / static_cast<double>(b.tick - a.tick);
}

/// True if car `s` respawned between a and b: it jumped to its last gate
/// at a tick neither snapshot shows, so there is no path between them to
/// draw (a line would slide it across the track); it stays at a until the
/// render tick reaches b.
bool teleported(const SnapshotStore::Entry& a, const SnapshotStore::Entry& b, std::size_t s) {
    return a.world.state.cars[s].respawns != b.world.state.cars[s].respawns;
}

}  // namespace

void Interpolator::set_rates(int tick_rate_hz, int snapshot_rate_hz) {
    ticks_per_snapshot_ = static_cast<double>(tick_rate_hz) / std::max(1, snapshot_rate_hz);
}

double Interpolator::render_tick(const SnapshotStore& store, std::uint64_t now_us, double period_us) const {
    if (store.newest_tick() == proto::kNoTick) return 0;
    // The render tick trails the newest snapshot by the interpolation delay,
    // advancing with the client's clock between snapshots.
    const double since = static_cast<double>(now_us - store.latest_at_us()) / period_us;
    return store.newest_tick() + since - delay_snapshots_ * ticks_per_snapshot_;
}

Vec3 Interpolator::other(const SnapshotStore& store, int slot, std::uint64_t now_us, double period_us) const {
    const auto s = static_cast<std::size_t>(slot);
    const WorldState& latest = store.latest().state;
    if (s >= latest.cars.size() || store.newest_tick() == proto::kNoTick) return Vec3::Zero();
    const double render = render_tick(store, now_us, period_us);
    const SnapshotStore::Entry* a = nullptr;
    const SnapshotStore::Entry* b = nullptr;
    bracket(store, s, render, a, b);
    if (a && b && !teleported(*a, *b, s)) {
        const Vec3& pa = a->world.state.cars[s].position;
        return pa + (b->world.state.cars[s].position - pa) * fraction(*a, *b, render);
    }
    if (a) return a->world.state.cars[s].position;  // never extrapolate
    if (b) return b->world.state.cars[s].position;
    return latest.cars[s].position;
}

bool Interpolator::span(const SnapshotStore& store, double render, std::uint32_t& from, std::uint32_t& to) {
    bool a = false, b = false;
    for (const SnapshotStore::Entry& e : store.entries()) {
        if (e.tick == proto::kNoTick) continue;
        if (e.tick <= render && (!a || e.tick > from)) {
            from = e.tick;
            a = true;
        }
        if (e.tick > render && (!b || e.tick < to)) {
            to = e.tick;
            b = true;
        }
    }
    return a && b;
}

void Interpolator::world(const SnapshotStore& store, std::uint64_t now_us, double period_us, WorldState& out) const {
    out = store.latest().state;
    if (store.newest_tick() == proto::kNoTick) return;
    const double render = render_tick(store, now_us, period_us);
    out.tick = static_cast<std::uint32_t>(std::clamp(std::floor(render), 0.0, static_cast<double>(out.tick)));
    for (std::size_t s = 0; s < out.cars.size(); ++s) {
        const SnapshotStore::Entry* a = nullptr;
        const SnapshotStore::Entry* b = nullptr;
        bracket(store, s, render, a, b);
        if (!a && !b) continue;  // the newest snapshot's
        out.cars[s] = (a ? a : b)->world.state.cars[s];
        if (!a || !b || teleported(*a, *b, s)) continue;  // never extrapolate
        const CarState& cb = b->world.state.cars[s];
        const double f = fraction(*a, *b, render);
        CarState& car = out.cars[s];
        car.position += (cb.position - car.position) * f;
        car.velocity += (cb.velocity - car.velocity) * f;
        // The shorter way round: q and -q are the same turn.
        const double sign = car.orientation.coeffs().dot(cb.orientation.coeffs()) < 0 ? -1.0 : 1.0;
        Eigen::Vector4d q = car.orientation.coeffs() * (1.0 - f) + cb.orientation.coeffs() * (sign * f);
        if (q.norm() > 0) q.normalize();
        car.orientation.coeffs() = q;
    }
}

}  // namespace jetrace::client
