#include "jetrace/core/race.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace {

namespace {

// squared_distance_to_gate for the car's next gate, from `memo` if it was
// computed there for that gate (same(): -0 and +0 give the same distance).
double gate_distance2(const Track& track, const CarState& car, GateDistanceMemo& memo) {
    if (memo.gate != car.next_checkpoint || !same(memo.at, car.position)) {
        memo.d2_m2 = squared_distance_to_gate(track.checkpoints[static_cast<std::size_t>(car.next_checkpoint)],
                                              car.position);
        memo.at = car.position;
        memo.gate = car.next_checkpoint;
    }
    return memo.d2_m2;
}

// The rules; kStill: for a car that did not move (`from` is its position),
// which cannot cross a gate (the test's two signed distances would be one
// number), its distance to the gate taken from `memo` where it was
// computed at that very place.
template <bool kStill>
void rules(const Track& track, const PhysicsSettings& ps, std::int32_t laps, std::uint32_t tick, bool racing,
           const Vec3& from, CarState& car, GateDistanceMemo* memo) {
    const auto gates = static_cast<std::int32_t>(track.checkpoints.size());
    if (!kStill && !car.finished && gates > 0) {
        const Checkpoint& gate = track.checkpoints[static_cast<std::size_t>(car.next_checkpoint)];
        const GateCrossing c = cross_gate(gate, from, car.position);
        if (c.crossed) {
            car.respawn_checkpoint = car.next_checkpoint;
            if (car.next_checkpoint == 0) {
                if (car.lap >= laps) {
                    car.finished = true;
                    car.finish_tick = tick;
                    car.finish_fraction = c.fraction;
                } else {
                    ++car.lap;
                }
            }
            car.next_checkpoint = (car.next_checkpoint + 1) % gates;
            car.best_gate_distance_m = kFarFromGate_m;
            car.no_progress_ticks = 0;
        }
    }
    bool lost = false;
    if (racing && !car.finished && gates > 0) {
        // Progress: the distance to the gate, in whole metres, went down.
        const double goal = static_cast<double>(car.best_gate_distance_m);
        const double d2 =
            kStill ? gate_distance2(track, car, *memo)
                   : squared_distance_to_gate(track.checkpoints[static_cast<std::size_t>(car.next_checkpoint)],
                                              car.position);
        if (d2 < goal * goal) {
            car.best_gate_distance_m = static_cast<std::int32_t>(std::floor(std::sqrt(d2)));
            car.no_progress_ticks = 0;
        } else {
            ++car.no_progress_ticks;
        }
        lost = static_cast<double>(car.no_progress_ticks) >= ps.no_progress_s * ps.tick_rate_hz;
    }
    if ((car.position.y() < track.kill_height_m || lost) && gates > 0) {
        place_car(car, track.checkpoints[static_cast<std::size_t>(car.respawn_checkpoint)].respawn);
        car.best_gate_distance_m = kFarFromGate_m;
        car.no_progress_ticks = 0;
        ++car.respawns;
    }
}

}  // namespace

void apply_race_rules(const Track& track, const PhysicsSettings& ps, std::int32_t laps, std::uint32_t tick,
                      bool racing, const Vec3& from, CarState& car) {
    rules<false>(track, ps, laps, tick, racing, from, car, nullptr);
}

void apply_race_rules_still(const Track& track, const PhysicsSettings& ps, std::int32_t laps, std::uint32_t tick,
                            bool racing, CarState& car, GateDistanceMemo& memo) {
    rules<true>(track, ps, laps, tick, racing, car.position, car, &memo);
}

int collide_cars(double radius_m, std::vector<CarState>& cars) {
    int pairs = 0;
    if (cars.size() < 2) return pairs;
    const double min_dist = 2.0 * radius_m;
    const double min2 = min_dist * min_dist;
    const std::size_t count = cars.size();
    CarState* const car = cars.data();
    for (std::size_t i = 0; i < count; ++i) {
        CarState& a = car[i];
        if (!a.active) continue;
        double ax = a.position.x();  // kept in a register while no pair moves `a`
        for (std::size_t j = i + 1; j < count; ++j) {
            CarState& b = car[j];
            // Apart along x alone: d2 below sums dx * dx with other squares,
            // never less (rounding is monotonic), so it would fail the test
            // below too. Most pairs are; this spares them the rest.
            const double dx = b.position.x() - ax;
            if (dx * dx >= min2 || !b.active) continue;
            const Vec3 d = b.position - a.position;
            const double d2 = d.squaredNorm();
            if (!(d2 < min2)) continue;
            const double dist = std::sqrt(d2);
            const Vec3 n = dist > 1e-9 ? Vec3(d / dist) : Vec3(1, 0, 0);
            ++pairs;
            const double half = 0.5 * (min_dist - dist);
            a.position -= n * half;
            b.position += n * half;
            const double closing = (b.velocity - a.velocity).dot(n);
            if (closing < 0.0) {
                a.velocity += n * (0.5 * closing);
                b.velocity -= n * (0.5 * closing);
            }
            ax = a.position.x();
        }
    }
    return pairs;
}

std::vector<Standing> standings(const Track& track, const std::vector<CarState>& cars, std::uint32_t start_tick,
                                int tick_rate_hz) {
    struct Key {
        Standing s;
        double progress_m;  // distance to next gate (smaller is better)
        std::uint32_t finish_tick;
        double fraction;
    };
    std::vector<Key> keys;
    for (std::size_t i = 0; i < cars.size(); ++i) {
        const CarState& c = cars[i];
        if (!c.active) continue;
        Key k;
        k.s.slot = static_cast<int>(i);
        k.s.finished = c.finished;
        k.s.lap = c.lap;
        k.s.next_checkpoint = c.next_checkpoint;
        k.finish_tick = c.finish_tick;
        k.fraction = c.finish_fraction;
        k.s.finish_time_s =
            c.finished ? (static_cast<double>(c.finish_tick) - start_tick + c.finish_fraction) / tick_rate_hz : 0.0;
        k.progress_m = track.checkpoints.empty()
                           ? 0.0
                           : distance_to_gate(track.checkpoints[static_cast<std::size_t>(c.next_checkpoint)], c.position);
        keys.push_back(k);
    }
    // Gates passed this lap: gate 0 is passed last, so it ranks highest.
    const auto gate_rank = [&](std::int32_t next) {
        return next == 0 ? static_cast<std::int32_t>(track.checkpoints.size()) : next;
    };
    std::stable_sort(keys.begin(), keys.end(), [&](const Key& a, const Key& b) {
        if (a.s.finished != b.s.finished) return a.s.finished;
        if (a.s.finished) {
            if (a.finish_tick != b.finish_tick) return a.finish_tick < b.finish_tick;
            if (a.fraction != b.fraction) return a.fraction < b.fraction;
            return a.s.slot < b.s.slot;
        }
        if (a.s.lap != b.s.lap) return a.s.lap > b.s.lap;
        if (gate_rank(a.s.next_checkpoint) != gate_rank(b.s.next_checkpoint))
            return gate_rank(a.s.next_checkpoint) > gate_rank(b.s.next_checkpoint);
        if (a.progress_m != b.progress_m) return a.progress_m < b.progress_m;
        return a.s.slot < b.s.slot;
    });
    std::vector<Standing> out;
    out.reserve(keys.size());
    for (const Key& k : keys) out.push_back(k.s);
    return out;
}

}  // namespace jetrace
