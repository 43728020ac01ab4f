#include "jetrace/core/world.hpp"

#include "jetrace/core/car_fields.hpp"
#include "jetrace/core/race.hpp"

#include <algorithm>
#include <cassert>
#include <cstdio>
#include <type_traits>

namespace jetrace {

Scene Scene::make(Track track, const PhysicsSettings& physics, double cell_size_m) {
    assert(validate(physics).empty());
    Scene s;
    s.grid = UniformGrid(track.triangles, track.bounds, physics.car_radius_m, cell_size_m);
    s.track = std::move(track);
    s.physics = physics;
    return s;
}

WorldState make_world(int slots, int laps, std::uint32_t start_tick) {
    WorldState w;
    w.cars.resize(static_cast<std::size_t>(slots));
    w.laps = laps;
    w.start_tick = start_tick;
    return w;
}

void spawn_car(const Scene& scene, WorldState& state, int slot, int spawn_index) {
    assert(slot >= 0 && static_cast<std::size_t>(slot) < state.cars.size());
    assert(!scene.track.spawns.empty());
    CarState car;
    car.active = true;
    const auto n = static_cast<int>(scene.track.spawns.size());
    place_car(car, scene.track.spawns[static_cast<std::size_t>(((spawn_index % n) + n) % n)]);
    state.cars[static_cast<std::size_t>(slot)] = car;
}

void remove_car(WorldState& state, int slot) { state.cars[static_cast<std::size_t>(slot)] = CarState{}; }

namespace {

// Sizes the scratch for n cars, every hint cleared (out of line: it runs
// once per car count).
[[gnu::noinline]] void resize_scratch(std::size_t n, StepScratch& s) {
    s.cars.clear();
    s.cars.resize(n);
}

inline void ensure_scratch(std::size_t n, StepScratch& s) {
    if (s.cars.size() != n) resize_scratch(n, s);
}

// Finds a car's contacts at `position` (ensure_contacts' slow path, out of
// line so that the common case, the contacts already known, costs a
// comparison and no call).
[[gnu::noinline]] void find_contacts_at(const Scene& sc, CarScratch& cs, const Vec3& position) {
    const TrackQuery q = sc.query();
    keep_covered(q, position, gather_reach(sc.physics, GatherFor::contacts), cs.candidates);
    find_contacts(q, cs.candidates, position, cs.contacts);
    cs.contacts_at = position;
    cs.contacts_valid = true;
}

// A car's contacts where it is: kept from the last query if it was at this
// very position (bit for bit), else found again.
inline void ensure_contacts(const Scene& sc, CarScratch& cs, const Vec3& position) {
    if (cs.contacts_valid && same(cs.contacts_at, position)) return;
    find_contacts_at(sc, cs, position);
}

// Rounds a car's orientation to the wire resolution, unless it is bit for
// bit what the last rounding produced (rounding is idempotent: a car that
// did not turn this step keeps its bits).
void quantize_orientation_cached(CarScratch& cs, CarState& car) {
    if (cs.quantized_valid && same_bits(cs.quantized_orientation, car.orientation)) return;
    quantize_orientation(car);
    cs.quantized_orientation = car.orientation;
    cs.quantized_valid = true;
}

using Motion = CarScratch::Motion;

bool same_motion(const CarState& car, const Motion& m) {
    return same_bits(car.position, m.position) && same_bits(car.velocity, m.velocity) &&
           same_bits(car.orientation, m.orientation);
}

Motion motion_of(const CarState& car) { return {car.position, car.velocity, car.orientation}; }

void set_motion(CarState& car, const Motion& m) {
    car.position = m.position;
    car.velocity = m.velocity;
    car.orientation = m.orientation;
}

// The input the step applies to car `i`: the brake before the start and
// after the finish, else the driver's (none if `inputs` has no entry).
Input effective_input(const WorldState& st, std::span<const Input> inputs, std::size_t i) {
    Input in{};
    if (st.tick < st.start_tick || st.cars[i].finished) {
        in.brake = 1;
    } else if (i < inputs.size()) {
        in = inputs[i];
    }
    return in;
}

// gather_for_step's gather, for a step moving `travel_m` (out of line:
// one step in dozens gathers). The gather's reach and look-ahead shape its
// region (never a result): worked out only when the step gathers.
[[gnu::noinline]] void gather_step_region(const Scene& sc, const Vec3& position, const Vec3& velocity,
                                          double travel_m, Candidates& cand) {
    const PhysicsSettings& ps = sc.physics;
    const GatherReach reach = gather_reach(ps, GatherFor::step, travel_m);
    cand.lookahead = gather_lookahead(ps, velocity, travel_m, cand.steps_served);
    gather_candidates(sc.query(), position, reach.gather_m, cand);
}

// The gather for a car's step from `position` at `velocity` (what
// drive_phase does). Inline: every moving car asks every step.
[[gnu::always_inline]] inline void gather_for_step(const Scene& sc, const Vec3& position, const Vec3& velocity,
                                                   CarScratch& cs) {
    const PhysicsSettings& ps = sc.physics;
    const double travel = velocity.norm() * ps.dt_s();
    Candidates& cand = cs.candidates;
    if (!cand.covers(position, step_cover(ps, travel))) gather_step_region(sc, position, velocity, travel, cand);
    ++cand.steps_served;
}

// Phase 1: sense contacts, apply controls and forces, integrate; a car at
// rest as its last step left it (CarScratch::rest) takes its motion after
// that step's phase 1 instead.
void drive_phase(const Scene& sc, WorldState& st, std::span<const Input> inputs, StepScratch& scr) {
    const PhysicsSettings& ps = sc.physics;
    for (std::size_t i = 0; i < st.cars.size(); ++i) {
        CarState& car = st.cars[i];
        if (!car.active) continue;
        CarScratch& cs = scr.cars[i];
        cs.previous_position = car.position;
        const Input in = effective_input(st, inputs, i);
        cs.asleep = cs.rest_valid && in == cs.rest_input && same_motion(car, cs.rest);
        if (cs.asleep) {
            if (cs.rest_moves) set_motion(car, cs.rest_mid);
            continue;
        }
        // A car starting at rest may end its step as it started: record
        // its motion in `rest` (valid again only if it does).
        cs.rest_valid = false;
        cs.candidate = car.velocity.x() == 0.0 && car.velocity.y() == 0.0 && car.velocity.z() == 0.0;
        if (cs.candidate) {
            cs.rest = motion_of(car);
            cs.rest_input = in;
        }
        gather_for_step(sc, car.position, car.velocity, cs);
        ensure_contacts(sc, cs, car.position);
        const Vec3 v0 = car.velocity;
        apply_controls_and_forces(ps, cs.contacts, in, car, cs.support);
        integrate(ps, v0, car);
        if (cs.candidate) cs.rest_mid = motion_of(car);
    }
}

// Phase 3 for one car: push it out of the track. `bumped`: the car
// collisions changed some car.
void resolve_car(const Scene& sc, CarState& car, CarScratch& cs, StepScratch& scr, bool bumped) {
    if (cs.asleep) {
        // Untouched by the car collisions: its step ends where the last did.
        if (!bumped || same_motion(car, cs.rest_mid)) {
            if (cs.rest_moves) set_motion(car, cs.rest);
            return;
        }
        // Pushed by a car: the whole step from here, from the gather on.
        cs.asleep = false;
        gather_for_step(sc, cs.rest.position, cs.rest.velocity, cs);
    }
    // Rounded to the wire resolution before the push-out, which then
    // checks the car where the step leaves it (resolve() rounds again
    // after any push).
    if (sc.physics.quantize_state) quantize_motion(car);
    // Exact shortcut: the resolver already found this very position
    // clear of every triangle, and only the position decides that (if
    // the step's motion needs no sweep, which also depends on where the
    // car came from).
    if (cs.clear_valid && same(cs.clear_at, car.position) &&
        !needs_sweep(sc.physics, cs.previous_position, car.position)) {
        return;
    }
    const ResolveStats r = resolve(sc.query(), {cs.previous_position, car.position, car.velocity}, cs.candidates,
                                   cs.contacts, cs.pushed_last);
    cs.pushed_last = r.pushes > 0;
    // The pass that found the car clear found its contacts there too.
    cs.contacts_valid = r.found_contacts;
    cs.contacts_at = car.position;
    scr.pushes += r.pushes;
    scr.max_passes = std::max(scr.max_passes, r.passes);
    scr.capped += r.capped ? 1 : 0;
    // Fewer pushing passes than allowed: the last pass found nothing touching.
    cs.clear_valid = r.passes < sc.physics.resolver_passes;
    cs.clear_at = car.position;
}

// Phase 4 for one car: gates, laps, respawn; find the contacts where the car
// now is (unless the push-out found them there) and align it to them;
// quantise orientation. Position and velocity are already quantised (phase
// 3, and a respawn places the car quantised).
void rules_car(const Scene& sc, const WorldState& st, CarState& car, CarScratch& cs) {
    const PhysicsSettings& ps = sc.physics;
    const std::uint32_t respawns = car.respawns;
    const bool racing = st.tick >= st.start_tick;
    if (cs.asleep) {
        // Parked: where the step began (its motion `rest`), and asking
        // for the gate distance of the same place tick after tick.
        assert(same_bits(car.position, cs.previous_position));
        apply_race_rules_still(sc.track, ps, st.laps, st.tick, racing, car, cs.gate_distance);
    } else {
        apply_race_rules(sc.track, ps, st.laps, st.tick, racing, cs.previous_position, car);
    }
    // Asleep (its motion `rest` again) and not respawned (the only way
    // the rules move a car): the alignment and rounding are the last step's.
    if (cs.asleep && car.respawns == respawns) return;
    ensure_contacts(sc, cs, car.position);
    align_to_contacts(ps, cs.contacts, car, cs.support);
    if (ps.quantize_state) quantize_orientation_cached(cs, car);
    // A step that left a car at rest exactly as it found it.
    cs.rest_valid = cs.candidate && same_motion(car, cs.rest);
    if (cs.rest_valid) cs.rest_moves = !same_motion(car, cs.rest_mid);
    cs.candidate = false;
}

// Phases 3 and 4, car after car: each car's push-out and rules read and
// change that car alone, so one pass over the cars does both.
void resolve_and_rules_phase(const Scene& sc, WorldState& st, StepScratch& scr, bool bumped) {
    scr.pushes = 0;
    scr.max_passes = 0;
    scr.capped = 0;
    for (std::size_t i = 0; i < st.cars.size(); ++i) {
        CarState& car = st.cars[i];
        if (!car.active) continue;
        CarScratch& cs = scr.cars[i];
        resolve_car(sc, car, cs, scr, bumped);
        rules_car(sc, st, car, cs);
    }
}

}  // namespace

void step(const Scene& scene, WorldState& state, std::span<const Input> inputs, StepScratch& scratch) {
    ensure_scratch(state.cars.size(), scratch);
    drive_phase(scene, state, inputs, scratch);
    const bool bumped = collide_cars(scene.physics.car_radius_m, state.cars) > 0;  // phase 2
    resolve_and_rules_phase(scene, state, scratch, bumped);  // phases 3 and 4
    ++state.tick;
}

void hash_car(Fnv1a& h, const CarState& c) {
    visit_car_fields(c, [&h](const char*, auto value) {
        using T = decltype(value);
        if constexpr (std::is_same_v<T, bool>) {
            h.u8(value ? 1 : 0);
        } else if constexpr (std::is_same_v<T, double>) {
            h.f64(value);
        } else if constexpr (std::is_same_v<T, std::int32_t>) {
            h.i32(value);
        } else {
            static_assert(std::is_same_v<T, std::uint32_t>);
            h.u32(value);
        }
    });
}

std::uint64_t car_hash(const CarState& c) {
    Fnv1a h;
    hash_car(h, c);
    return h.value();
}

std::uint64_t state_hash(const WorldState& s) {
    Fnv1a h;
    h.u32(s.tick);
    h.u32(s.start_tick);
    h.i32(s.laps);
    h.u32(static_cast<std::uint32_t>(s.cars.size()));
    for (const CarState& c : s.cars) hash_car(h, c);
    return h.value();
}

std::string hash_hex(std::uint64_t h) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

}  // namespace jetrace
