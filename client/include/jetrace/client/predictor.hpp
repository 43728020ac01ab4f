// The client's prediction: the world run ahead of the server with the own
// car's inputs and the others' best known ones, and its reconciliation with
// each authoritative snapshot.
//
// Reconciling replays only what can differ. Each predicted tick keeps the
// world it started from and the inputs it was stepped with (a ring of
// kFrames ticks). When the snapshot's world equals the one predicted for its
// tick, bit for bit, every tick whose inputs are still the best known ones
// would be stepped again to the very same world (the step is deterministic
// and its scratch never changes a result): the replay starts at the first
// tick whose inputs the snapshot now knows better, or is skipped. The world
// so reached is the one a full replay from the snapshot gives.
//
// A replayed tick steps only the cars that can end it elsewhere than the
// kept prediction: a car whose state and input are the kept ones, and which
// is far from every changed car in both worlds (no car-car contact can reach
// it within the tick), ends the tick where the kept next tick has it, since
// every phase of the step but the car-car one is per car. So does a group of
// such cars near each other but far from every changed one. Inputs compare
// as the step uses them: none before the start or for a finished car.
//
// A thin predictor (thin = true) never steps: its world is the newest
// snapshot's, its tick runs on with the clock, and it keeps only the own
// inputs, for sending.
#pragma once

#include "jetrace/client/client_config.hpp"
#include "jetrace/core/tick_ring.hpp"
#include "jetrace/core/world.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/proto/world_codec.hpp"

#include <array>
#include <cassert>
#include <cstdint>
#include <vector>

namespace jetrace::client {

class Predictor {
public:
    /// What reconcile() found.
    struct Outcome {
        /// The snapshot was at or ahead of the prediction: its world was taken.
        bool resynced = false;
        /// The own car's prediction for the snapshot's tick differed from it.
        bool corrected = false;
        /// The own car's position error then (unit: m).
        double error_m = 0;
        /// Another car came within 4 car radii of the own one at a replayed
        /// tick, in the prediction replaced or in the replay: a touch with
        /// a car whose inputs were guessed can have moved the own car.
        bool near_car = false;
    };
    /// Work done since the start (reconciliation ticks replayed, and
    /// reconciliations that needed no replay at all).
    struct Work {
        std::uint64_t replayed_ticks = 0;
        std::uint64_t skipped_replays = 0;
        /// Car-steps of the replayed ticks taken from the kept prediction.
        std::uint64_t reused_car_steps = 0;
    };

    /// `input_delay_ticks`: the own input given to run_tick() at tick t is
    /// for tick t + input_delay_ticks (ClientConfig::input_delay_ticks).
    explicit Predictor(bool thin = false, std::uint32_t input_delay_ticks = 0)
        : thin_(thin), delay_(input_delay_ticks) {
        assert(input_delay_ticks <= kMaxInputDelayTicks);
    }

    /// Forgets the world, the inputs and the kept ticks.
    void reset();
    /// Starts predicting from an authoritative world.
    void start(const WorldState& w);
    /// Drops the step's scratch (it holds a track's triangles).
    void clear_scratch() { scratch_ = StepScratch{}; }
    const WorldState& world() const { return world_; }
    bool thin() const { return thin_; }

    /// Steps the world one tick: the own car (slot `own`) with its input for
    /// the tick, the others with the inputs `latest` knows for it. `mine` is
    /// the own input for the tick input_delay_ticks later (with no delay,
    /// this one); a tick no input was given for (the first ones, or after
    /// the clock jumped) gets a neutral one, sent like the others.
    void run_tick(const Scene& scene, std::size_t own, const Input& mine, const proto::WorldSnapshot& latest);
    /// Restores the snapshot's world and brings it back to the predicted
    /// tick (see the file comment). `check_own`: compare the own car with its
    /// prediction (not while spectating or inactive).
    Outcome reconcile(const Scene& scene, const proto::WorldSnapshot& snap, std::size_t own, bool check_own);

    /// The own input used for tick t, or nullptr if none is kept.
    const Input* my_input(std::uint32_t t) const { return my_inputs_.find(t); }
    /// Fills `b` (first_tick, inputs) with the own inputs the server has not
    /// applied yet: after `last_applied` (kNoTick: none), up to the predicted
    /// tick (plus the input delay), at most kMaxInputsPerBatch, none older
    /// than a gap. False: none.
    bool unapplied_inputs(std::uint32_t last_applied, proto::InputBatch& b) const;
    const Work& work() const { return work_; }

private:
    static constexpr std::size_t kRing = 256;
    static_assert(kMaxInputDelayTicks < kRing / 2);
    /// Ticks whose start world is kept (more than the largest lead).
    static constexpr std::size_t kFrames = 64;
    struct Frame {
        WorldState world;  // at the start of the tick
        std::vector<Input> inputs;  // stepped with
    };

    /// The inputs tick t is stepped with, given the snapshot: the others'
    /// known ones, the own one kept for t (else the snapshot's for it).
    void fill_inputs(const proto::WorldSnapshot& snap, std::size_t own, std::uint32_t t, std::vector<Input>& out) const;
    /// Keeps the frame of tick w.tick and `near` (another car near the own
    /// one at its start: near_other_car, with every car active), then steps
    /// w with `inputs`.
    void step_kept(const Scene& scene, WorldState& w, const std::vector<Input>& inputs, std::size_t own, bool near);
    /// The first tick from which the prediction must be stepped again.
    std::uint32_t first_stale_tick(const proto::WorldSnapshot& snap, std::size_t own, std::uint32_t target);
    bool holds(std::uint32_t t) const { return frames_.has(t); }
    /// The kept frame of tick t (holds(t)).
    const Frame& frame(std::uint32_t t) const { return *frames_.find(t); }
    void reconcile_thin(const proto::WorldSnapshot& snap, Outcome& o);
    /// Steps replay_ through tick t (< target), reusing the kept next tick
    /// for the cars it can (see the file comment).
    void replay_tick(const Scene& scene, const proto::WorldSnapshot& snap, std::size_t own, std::uint32_t t,
                     std::uint32_t target);
    /// Marks in reuse_ the cars of replay_ that tick t need not step.
    bool find_reusable(const Scene& scene, const Frame& kept);

    bool thin_ = false;
    std::uint32_t delay_ = 0;
    WorldState world_;
    WorldState replay_;  // the replay's world
    StepScratch scratch_;
    TickRing<Input, kRing> my_inputs_;
    TickRing<CarState, kRing> my_states_;  // own car at the start of tick t
    TickRing<char, kRing> near_;  // another car near the own one then (near_other_car)
    TickRing<Frame, kFrames> frames_;
    std::vector<Input> inputs_;  // of the tick being stepped
    std::vector<char> reuse_;  // per car: taken from the kept next tick
    std::vector<std::uint32_t> parent_;  // groups of cars within reach
    std::vector<char> changed_;  // per group root: holds a changed car
    std::vector<std::uint32_t> order_;  // cars by x (the reach test)
    bool near_replay_ = false;  // Outcome::near_car of the replay under way
    Work work_;
};

/// Whether another active car is within 4 car radii of car `own` in `w`:
/// close enough that a touch with it within a few ticks is possible.
bool near_other_car(const Scene& scene, const WorldState& w, std::size_t own);

/// Whether two worlds are equal bit for bit (tick, rules and every car field).
bool same_world(const WorldState& a, const WorldState& b);

}  // namespace jetrace::client
