// Where the client draws cars: its own one at the prediction plus a
// correction offset that fades out (kept apart from the simulated state),
// the others interpolated between two stored snapshots around a render
// tick that trails the newest snapshot (never extrapolated, and never
// across a respawn: a car that respawned between the two is drawn where
// the older one has it until the render tick reaches the newer).
#pragma once

#include "jetrace/client/snapshot_store.hpp"
#include "jetrace/core/world.hpp"

#include <cstdint>

namespace jetrace::client {

class Interpolator {
public:
    /// interpolation_snapshots: delay behind the newest snapshot (unit:
    /// snapshot intervals); smoothing_per_tick: fraction of the offset
    /// removed per tick (unit: 1/tick).
    Interpolator(double interpolation_snapshots, double smoothing_per_tick)
        : delay_snapshots_(interpolation_snapshots), smoothing_per_tick_(smoothing_per_tick) {}

    /// Snapshot rate assumed before a Welcome names the server's (unit: Hz).
    static constexpr int kDefaultSnapshotRateHz = 60;

    /// The server's tick and snapshot rates (unit: Hz).
    void set_rates(int tick_rate_hz, int snapshot_rate_hz = kDefaultSnapshotRateHz);
    void reset() { offset_ = Vec3::Zero(); }
    /// A reconciliation moved the predicted own car from `before` to `after`:
    /// it is still drawn at `before`, the offset fading from there; unless
    /// the correction `respawned` it (its respawn count changed: a jump to
    /// its last gate, or back), which is drawn at once rather than slid
    /// across the track.
    void correct(const Vec3& before, const Vec3& after, bool respawned) {
        offset_ = respawned ? Vec3::Zero() : Vec3(offset_ + before - after);
    }
    /// One predicted tick: the offset fades, and is gone once under a
    /// micrometre (so that the car is drawn exactly where it is predicted).
    void tick() {
        offset_ *= 1.0 - smoothing_per_tick_;
        if (offset_.squaredNorm() < kGoneM * kGoneM) offset_ = Vec3::Zero();
    }
    /// A correction offset is still fading.
    bool smoothing() const { return !(offset_ == Vec3::Zero()); }

    Vec3 own(const Vec3& predicted) const { return smoothing() ? Vec3(predicted + offset_) : predicted; }
    /// Another car, at `now_us` on a clock of period `period_us` (unit: µs).
    Vec3 other(const SnapshotStore& store, int slot, std::uint64_t now_us, double period_us) const;
    /// The render tick at `now_us`: the newest snapshot's tick, plus the
    /// ticks since it arrived, less the delay (unit: ticks; fractional).
    double render_tick(const SnapshotStore& store, std::uint64_t now_us, double period_us) const;
    /// Every car at the render tick, as other() places it (velocity
    /// interpolated alike, orientation normalised-linearly), the other
    /// fields from the stored snapshot at or before the render tick; the
    /// rules and the cars no stored snapshot brackets from the newest
    /// snapshot; `tick` the render tick rounded down. For drawing only.
    void world(const SnapshotStore& store, std::uint64_t now_us, double period_us, WorldState& out) const;
    /// The ticks of the stored snapshots around `render`: the newest at or
    /// before it (from) and the oldest after it (to); false unless both exist.
    static bool span(const SnapshotStore& store, double render, std::uint32_t& from, std::uint32_t& to);

private:
    static constexpr double kGoneM = 1e-6;
    double delay_snapshots_;
    double smoothing_per_tick_;
    double ticks_per_snapshot_ = 1.0;
    Vec3 offset_{0, 0, 0};
};

}  // namespace jetrace::client
