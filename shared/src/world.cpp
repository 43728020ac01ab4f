#include "jetrace/world.hpp"

#include "jetrace/race.hpp"

#include <algorithm>
#include <cassert>
#include <cstdio>
#include <cstring>

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

// Sizes the scratch for n cars (out of line: it runs once per car count).
[[gnu::noinline]] void resize_scratch(std::size_t n, StepScratch& s) {
    s.candidates.resize(n);
    s.contacts.resize(n);
    s.contacts_at.resize(n);
    s.contacts_valid.assign(n, 0);
    s.previous_position.resize(n);
    s.clear_at.resize(n);
    s.clear_valid.assign(n, 0);
    s.pushed_last.assign(n, 0);
    s.quantized_orientation.resize(n);
    s.quantized_valid.assign(n, 0);
}

inline void ensure_scratch(std::size_t n, StepScratch& s) {
    if (s.candidates.size() != n) resize_scratch(n, s);
}

// Finds the contacts of car i at `position` (ensure_contacts' slow path,
// out of line so that the common case, the contacts already known, costs a
// comparison and no call).
[[gnu::noinline]] void find_contacts_at(const Scene& sc, StepScratch& scr, std::size_t i, const Vec3& position) {
    Candidates& cand = scr.candidates[i];
    keep_covered(sc.grid, sc.track, sc.broadphase, position, sc.physics.car_radius_m + sc.physics.contact_skin_m, cand);
    find_contacts(sc.track, cand, sc.physics, position, scr.contacts[i]);
    scr.contacts_at[i] = position;
    scr.contacts_valid[i] = 1;
}

// The contacts of car i where it is: kept from the last query if it was at
// this very position (bit for bit), else found again.
inline void ensure_contacts(const Scene& sc, StepScratch& scr, std::size_t i, const Vec3& position) {
    if (scr.contacts_valid[i] && same(scr.contacts_at[i], position)) return;
    find_contacts_at(sc, scr, i, position);
}

// Rounds car i's orientation to the wire resolution, unless it is bit for
// bit what the last rounding produced (rounding is idempotent: a car that
// did not turn this step keeps its bits).
void quantize_orientation_cached(StepScratch& scr, std::size_t i, CarState& car) {
    if (scr.quantized_valid[i] &&
        std::memcmp(scr.quantized_orientation[i].coeffs().data(), car.orientation.coeffs().data(), 4 * sizeof(double)) == 0) {
        return;
    }
    quantize_orientation(car);
    scr.quantized_orientation[i] = car.orientation;
    scr.quantized_valid[i] = 1;
}

// Phase 1: sense contacts, apply controls and forces, integrate.
void drive_phase(const Scene& sc, WorldState& st, std::span<const Input> inputs, StepScratch& scr) {
    const PhysicsSettings& ps = sc.physics;
    const bool racing = st.tick >= st.start_tick;
    for (std::size_t i = 0; i < st.cars.size(); ++i) {
        CarState& car = st.cars[i];
        if (!car.active) continue;
        scr.previous_position[i] = car.position;
        Input in{};
        if (!racing || car.finished) {
            in.brake = 1;
        } else if (i < inputs.size()) {
            in = inputs[i];
        }
        const double travel = car.velocity.norm() * ps.dt_s();
        const double reach = ps.car_radius_m + ps.contact_skin_m + travel + kGatherMargin_m;
        Candidates& cand = scr.candidates[i];
        const double ahead = travel * kGatherLookahead_steps;
        cand.lookahead = car.velocity * (ps.dt_s() * kGatherLookahead_steps);
        if (ahead > kGatherLookaheadMax_m) cand.lookahead *= kGatherLookaheadMax_m / ahead;
        if (!cand.covers(car.position, reach - kGatherMargin_m)) {
            // Wide enough for this step's sweep too (its motion is about
            // `travel`; kGatherMargin_m absorbs the step's acceleration), so
            // that the sweep does not gather again.
            const double gather_m = ps.collision_mode == CollisionMode::swept
                                        ? std::max(reach, sweep_reach(ps, travel) + kGatherMargin_m)
                                        : reach;
            gather_candidates(sc.grid, sc.track, sc.broadphase, car.position, gather_m, cand);
        }
        ensure_contacts(sc, scr, i, car.position);
        const Vec3 v0 = car.velocity;
        apply_controls_and_forces(ps, scr.contacts[i], in, car);
        integrate(ps, v0, car);
    }
}

// Phase 3: push each car out of the track.
void resolve_phase(const Scene& sc, WorldState& st, StepScratch& scr) {
    scr.pushes = 0;
    scr.max_passes = 0;
    scr.capped = 0;
    for (std::size_t i = 0; i < st.cars.size(); ++i) {
        CarState& car = st.cars[i];
        if (!car.active) continue;
        // Rounded to the wire resolution before the push-out, which then
        // checks the car where the step leaves it (resolve() rounds again
        // after any push).
        if (sc.physics.quantize_state) quantize_motion(car);
        // Exact shortcut: the resolver already found this very position
        // clear of every triangle, and only the position decides that (if
        // the step's motion needs no sweep, which also depends on where the
        // car came from).
        if (scr.clear_valid[i] && same(scr.clear_at[i], car.position) &&
            !needs_sweep(sc.physics, scr.previous_position[i], car.position)) {
            continue;
        }
        const ResolveStats r = resolve(sc.track, sc.grid, sc.broadphase, sc.physics, scr.previous_position[i],
                                       car.position, car.velocity, scr.candidates[i], scr.contacts[i],
                                       scr.pushed_last[i] != 0);
        scr.pushed_last[i] = r.pushes > 0 ? 1 : 0;
        // The pass that found the car clear found its contacts there too.
        scr.contacts_valid[i] = r.found_contacts ? 1 : 0;
        scr.contacts_at[i] = car.position;
        scr.pushes += r.pushes;
        scr.max_passes = std::max(scr.max_passes, r.passes);
        scr.capped += r.capped ? 1 : 0;
        // Fewer pushing passes than allowed: the last pass found nothing touching.
        scr.clear_valid[i] = r.passes < sc.physics.resolver_passes ? 1 : 0;
        scr.clear_at[i] = car.position;
    }
}

// Phase 4: gates, laps, respawn; find the contacts where the car now is
// (unless the push-out found them there) and align it to them; quantise
// orientation. Position and velocity are already quantised (phase 3, and a
// respawn places the car quantised).
void rules_phase(const Scene& sc, WorldState& st, StepScratch& scr) {
    const PhysicsSettings& ps = sc.physics;
    for (std::size_t i = 0; i < st.cars.size(); ++i) {
        CarState& car = st.cars[i];
        if (!car.active) continue;
        apply_race_rules(sc.track, ps, st.laps, st.tick, st.tick >= st.start_tick, scr.previous_position[i], car);
        ensure_contacts(sc, scr, i, car.position);
        align_to_contacts(ps, scr.contacts[i], car);
        if (ps.quantize_state) quantize_orientation_cached(scr, i, car);
    }
}

}  // namespace

void step(const Scene& scene, WorldState& state, std::span<const Input> inputs, StepScratch& scratch) {
    ensure_scratch(state.cars.size(), scratch);
    drive_phase(scene, state, inputs, scratch);
    collide_cars(scene.physics.car_radius_m, state.cars);  // phase 2
    resolve_phase(scene, state, scratch);
    rules_phase(scene, state, scratch);
    ++state.tick;
}

void hash_car(Fnv1a& h, const CarState& c) {
    h.u8(c.active ? 1 : 0);
    h.u8(c.finished ? 1 : 0);
    h.vec3(c.position);
    h.vec3(c.velocity);
    h.f64(c.orientation.w());
    h.f64(c.orientation.x());
    h.f64(c.orientation.y());
    h.f64(c.orientation.z());
    h.i32(c.next_checkpoint);
    h.i32(c.lap);
    h.i32(c.respawn_checkpoint);
    h.u32(c.finish_tick);
    h.f64(c.finish_fraction);
    h.u32(c.respawns);
    h.i32(c.best_gate_distance_m);
    h.u32(c.no_progress_ticks);
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
