// The world: an immutable Scene (track, grid, settings) and a plain-value
// WorldState stepped by step(scene, state, inputs). Saving is copying the
// state; restoring is assigning it. That is also what reconciliation does.
#pragma once

#include "jetrace/core/hovercar.hpp"
#include "jetrace/core/race.hpp"
#include "jetrace/core/resolver.hpp"
#include "jetrace/core/settings.hpp"
#include "jetrace/core/track.hpp"
#include "jetrace/core/uniform_grid.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace jetrace {

/// Everything that does not change during a race.
struct Scene {
    Track track;
    UniformGrid grid;
    PhysicsSettings physics;
    Broadphase broadphase = Broadphase::grid;

    /// What the resolver reads (references into this scene).
    TrackQuery query() const { return {track, grid, broadphase, physics}; }

    /// Builds the grid. `physics` must be valid (see validate()).
    static Scene make(Track track, const PhysicsSettings& physics, double cell_size_m = 0.0);
};

/// Everything that changes. A value type: copy to save, assign to restore.
struct WorldState {
    /// Ticks stepped since the world was created.
    std::uint32_t tick = 0;
    /// Inputs are ignored (cars held with the brake) before this tick.
    std::uint32_t start_tick = 0;
    /// Laps to finish the race.
    std::int32_t laps = 1;
    /// Fixed slots; inactive slots are skipped.
    std::vector<CarState> cars;
};

/// One car's part of the step scratch (one struct per car, so that a phase
/// reaches all of a car's scratch through one pointer).
struct CarScratch {
    Candidates candidates;
    /// Contacts of the car at the end of the last step, and the position
    /// they were found at: reused by the next step only if the car is still
    /// exactly there (bit for bit), else found again.
    Contacts contacts;
    Vec3 contacts_at{0, 0, 0};
    bool contacts_valid = false;
    Vec3 previous_position{0, 0, 0};
    /// A position the resolver last left the car at, clear of the track: a
    /// car found there again (at rest) needs no push-out test.
    Vec3 clear_at{0, 0, 0};
    bool clear_valid = false;
    /// Whether the car was pushed out in its last resolve (a hint that saves
    /// work, never changes a result; see resolve()).
    bool pushed_last = false;
    /// The orientation the car's last rounding produced: a car found with
    /// exactly these bits (one that did not turn) needs no rounding.
    Quat quantized_orientation{1, 0, 0, 0};
    bool quantized_valid = false;
    /// The unit orientation and support frame of the car's last controls and
    /// alignment (see SupportMemo).
    SupportMemo support;
    /// A car at rest (a parked car, one waiting for the start, a finished
    /// one held by the brake): its last step, with input `rest_input`,
    /// left its motion (position, velocity, orientation) `rest` bit for bit
    /// as it found it, with `rest_mid` after the controls and integration.
    /// Found there again with that input, the step is a function of those
    /// alone, so it gives the same: the car takes `rest_mid` for the car
    /// collisions and, if no car touched it, `rest` again without the
    /// contacts, forces, push-out or alignment. The race rules still run.
    /// `rest_moves`: `rest_mid` differs from `rest` (a car held still by the
    /// track, not standing still in mid-step, is copied twice).
    struct Motion {
        Vec3 position{0, 0, 0};
        Vec3 velocity{0, 0, 0};
        Quat orientation{1, 0, 0, 0};
    };
    Motion rest;
    Motion rest_mid;
    Input rest_input{};
    bool rest_valid = false;
    bool rest_moves = false;
    /// This step: the car started it with a zero velocity (its motion and
    /// input are recorded in `rest`, valid if the step ends where it
    /// began), or it is taking the shortcut (`asleep`).
    bool candidate = false;
    bool asleep = false;
    /// The race rules' distance to the next gate, where they last measured
    /// it for this car asleep.
    GateDistanceMemo gate_distance;
};

/// Per-step scratch owned by the caller; results never depend on its contents.
/// It belongs to one Scene: its candidates and kept frames name that
/// scene's triangles, so stepping another scene (one made in the same
/// place included) needs fresh scratch (StepScratch{}).
struct StepScratch {
    /// One per car slot.
    std::vector<CarScratch> cars;
    /// Push-outs, most pushing passes of one car, and capped resolves in the
    /// last step (diagnostics).
    int pushes = 0;
    int max_passes = 0;
    int capped = 0;
};

/// A world with `slots` empty car slots.
WorldState make_world(int slots, int laps, std::uint32_t start_tick = 0);

/// Puts a car into slot `slot` at spawn `spawn_index` (mod spawn count).
void spawn_car(const Scene& scene, WorldState& state, int slot, int spawn_index);
/// Removes a car (its slot becomes inactive).
void remove_car(WorldState& state, int slot);

/// Advances the world by one fixed step. `inputs` has one entry per slot.
void step(const Scene& scene, WorldState& state, std::span<const Input> inputs, StepScratch& scratch);

/// 64-bit hash over the raw bits of the whole state, in slot order.
std::uint64_t state_hash(const WorldState& state);
/// Feeds every field of one car, raw bits, into `h`.
void hash_car(Fnv1a& h, const CarState& car);
/// Hash of one car (equal hashes: bit-identical cars, for all practical purposes).
std::uint64_t car_hash(const CarState& car);
/// 16 lowercase hex digits.
std::string hash_hex(std::uint64_t h);

/// A convenience owner of a scene reference, a state and scratch.
class World {
public:
    World(const Scene& scene, WorldState state) : scene_(&scene), state_(std::move(state)) {}
    void step(std::span<const Input> inputs) { jetrace::step(*scene_, state_, inputs, scratch_); }
    const WorldState& state() const { return state_; }
    WorldState& state() { return state_; }
    WorldState save() const { return state_; }
    void restore(const WorldState& s) { state_ = s; }
    std::uint64_t hash() const { return state_hash(state_); }
    const Scene& scene() const { return *scene_; }
    const StepScratch& scratch() const { return scratch_; }

private:
    const Scene* scene_;
    WorldState state_;
    StepScratch scratch_;
};

}  // namespace jetrace
