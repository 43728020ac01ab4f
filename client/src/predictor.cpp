#include "jetrace/client/predictor.hpp"

#include "jetrace/core/car_fields.hpp"

#include <algorithm>
#include <cstring>

namespace jetrace::client {

namespace {

// The best guess of car `slot`'s input at tick t from a snapshot: the input
// the server already holds for t if the snapshot carries it, else the newest
// one known.
Input known_input(const proto::WorldSnapshot& snap, std::size_t slot, std::uint32_t t) {
    if (slot >= snap.last_inputs.size()) return Input{};
    if (slot < snap.upcoming.size() && !snap.upcoming[slot].empty()) {
        const auto& up = snap.upcoming[slot];
        const std::uint32_t k = t >= snap.state.tick ? t - snap.state.tick : 0;
        return k < up.size() ? up[k] : up.back();
    }
    return snap.last_inputs[slot];
}

// Bit for bit, field by field (never the padding): -0 and 0 differ.
bool same_car(const CarState& a, const CarState& b) { return car_field_bits(a) == car_field_bits(b); }

std::uint32_t root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

// Joins in `parent` (a union-find forest) every two active cars of `w`
// closer than `reach` (sorted by x, then a sweep: no pair test beyond reach
// in x).
void join_near(const WorldState& w, double reach, std::vector<std::uint32_t>& order,
               std::vector<std::uint32_t>& parent) {
    order.clear();
    for (std::uint32_t i = 0; i < w.cars.size(); ++i) {
        if (w.cars[i].active) order.push_back(i);
    }
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        const double xa = w.cars[a].position.x(), xb = w.cars[b].position.x();
        return xa < xb || (xa == xb && a < b);
    });
    const double reach2 = reach * reach;
    for (std::size_t a = 0; a < order.size(); ++a) {
        const Vec3& pa = w.cars[order[a]].position;
        for (std::size_t b = a + 1; b < order.size(); ++b) {
            const Vec3& pb = w.cars[order[b]].position;
            if (pb.x() - pa.x() >= reach) break;
            if ((pb - pa).squaredNorm() < reach2) parent[root(parent, order[a])] = root(parent, order[b]);
        }
    }
}

// The inputs that tick w.tick uses: none before the start, for a finished
// car or an empty slot (the step brakes or skips them).
void effective_inputs(const WorldState& w, std::vector<Input>& in) {
    for (std::size_t s = 0; s < in.size() && s < w.cars.size(); ++s) {
        if (w.tick < w.start_tick || !w.cars[s].active || w.cars[s].finished) in[s] = Input{};
    }
}

}  // namespace

bool same_world(const WorldState& a, const WorldState& b) {
    if (a.tick != b.tick || a.start_tick != b.start_tick || a.laps != b.laps || a.cars.size() != b.cars.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.cars.size(); ++i) {
        if (!same_car(a.cars[i], b.cars[i])) return false;
    }
    return true;
}

void Predictor::reset() {
    my_inputs_.clear();
    my_states_.clear();
    near_.clear();
    frames_.clear();
}

void Predictor::start(const WorldState& w) { world_ = w; }

bool Predictor::unapplied_inputs(std::uint32_t last_applied, proto::InputBatch& b) const {
    const std::uint32_t end = world_.tick + delay_;  // inputs for ticks < end exist
    std::uint32_t first = last_applied == proto::kNoTick ? 0 : last_applied + 1;
    const auto most = static_cast<std::uint32_t>(proto::kMaxInputsPerBatch);
    if (end > most && first < end - most) first = end - most;
    b.inputs.clear();
    for (std::uint32_t t = first; t < end; ++t) {
        const Input* in = my_input(t);
        if (in == nullptr) {
            b.inputs.clear();
            first = t + 1;
            continue;
        }
        b.inputs.push_back(*in);
    }
    b.first_tick = first;
    return !b.inputs.empty();
}

void Predictor::fill_inputs(const proto::WorldSnapshot& snap, std::size_t own, std::uint32_t t,
                            std::vector<Input>& out) const {
    out.resize(snap.state.cars.size());
    for (std::size_t s = 0; s < out.size(); ++s) out[s] = known_input(snap, s, t);
    if (const Input* mine = my_input(t); mine != nullptr && own < out.size()) out[own] = *mine;
}

void Predictor::step_kept(const Scene& scene, WorldState& w, const std::vector<Input>& inputs, std::size_t own,
                          bool near) {
    const std::uint32_t t = w.tick;
    my_states_.insert(t, w.cars[own]);
    near_.insert(t, near ? 1 : 0);
    near_replay_ = near_replay_ || near;
    Frame& f = frames_.insert(t);
    f.world = w;  // reuses the frame's storage
    f.inputs = inputs;
    step(scene, w, inputs, scratch_);
}

void Predictor::run_tick(const Scene& scene, std::size_t own, const Input& mine, const proto::WorldSnapshot& latest) {
    const std::uint32_t t = world_.tick;
    // With an input delay, ticks t .. t + delay - 1 have their inputs from
    // earlier ticks; any that has none (the first ticks, or the clock jumped)
    // gets a neutral one now, so that the inputs sent have no gap.
    for (std::uint32_t k = t; k != t + delay_; ++k) {
        if (!my_inputs_.has(k)) my_inputs_.insert(k, Input{});
    }
    my_inputs_.insert(t + delay_, mine);
    if (thin_) {
        ++world_.tick;
        return;
    }
    fill_inputs(latest, own, t, inputs_);
    inputs_.resize(world_.cars.size());
    effective_inputs(world_, inputs_);
    step_kept(scene, world_, inputs_, own, near_other_car(scene, world_, own));
}

std::uint32_t Predictor::first_stale_tick(const proto::WorldSnapshot& snap, std::size_t own, std::uint32_t target) {
    const std::uint32_t S = snap.state.tick;
    if (!holds(S) || !same_world(frame(S).world, snap.state)) return S;
    std::uint32_t t = S;
    while (t < target && holds(t)) {
        fill_inputs(snap, own, t, inputs_);
        effective_inputs(frame(t).world, inputs_);  // the new world at t, so far
        if (inputs_ != frame(t).inputs) return t;
        ++t;
    }
    // Every tick up to the target agrees: nothing to step again. A frame
    // missing before it (never, with kFrames above the largest lead) means a
    // full replay.
    return t == target ? target : S;
}

void Predictor::reconcile_thin(const proto::WorldSnapshot& snap, Outcome& o) {
    if (snap.state.tick >= world_.tick) {
        world_ = snap.state;
        o.resynced = true;
        return;
    }
    const std::uint32_t tick = world_.tick;
    world_ = snap.state;
    world_.tick = tick;
}

Predictor::Outcome Predictor::reconcile(const Scene& scene, const proto::WorldSnapshot& snap, std::size_t own,
                                        bool check_own) {
    Outcome o;
    if (thin_) {
        reconcile_thin(snap, o);
        return o;
    }
    const std::uint32_t S = snap.state.tick;
    if (S >= world_.tick) {
        // Behind the server: take its state (the clock catches up).
        world_ = snap.state;
        o.resynced = true;
        return o;
    }
    if (const CarState* mine = check_own ? my_states_.find(S) : nullptr) {
        if (car_hash(*mine) != car_hash(snap.state.cars[own])) {
            o.corrected = true;
            o.error_m = (mine->position - snap.state.cars[own].position).norm();
        }
    }
    // Restore the server's state and replay the ticks since with our own
    // inputs and the others' best known ones, from the first that can differ.
    const std::uint32_t target = world_.tick;
    const std::uint32_t from = first_stale_tick(snap, own, target);
    if (from == target) {
        ++work_.skipped_replays;
        return o;
    }
    replay_ = from == S ? snap.state : frame(from).world;
    near_replay_ = near_other_car(scene, world_, own);
    for (std::uint32_t t = from; t < target; ++t) replay_tick(scene, snap, own, t, target);
    o.near_car = near_replay_ || near_other_car(scene, replay_, own);
    std::swap(world_, replay_);  // both keep their storage
    work_.replayed_ticks += target - from;
    return o;
}

bool near_other_car(const Scene& scene, const WorldState& w, std::size_t own) {
    if (own >= w.cars.size()) return false;
    const double near_m = 4.0 * scene.physics.car_radius_m;
    for (std::size_t j = 0; j < w.cars.size(); ++j) {
        if (j == own || !w.cars[j].active) continue;
        if ((w.cars[j].position - w.cars[own].position).squaredNorm() < near_m * near_m) return true;
    }
    return false;
}

bool Predictor::find_reusable(const Scene& scene, const Frame& kept) {
    const std::size_t n = replay_.cars.size();
    reuse_.assign(n, 0);
    if (kept.world.cars.size() != n || kept.inputs.size() != n) return false;
    // Reach: both cars' travel in the tick, generously, plus the car-car
    // push-outs of a pile (each at most half an overlap), on top of contact.
    const std::array<const WorldState*, 2> worlds{&replay_, &kept.world};
    double v_max = 0;
    for (const WorldState* w : worlds) {
        for (const CarState& c : w->cars) {
            if (c.active) v_max = std::max(v_max, c.velocity.norm());
        }
    }
    const double r = scene.physics.car_radius_m;
    const double reach = 4.0 * r + 8.0 * v_max * scene.physics.dt_s() + 1.0;
    // Groups of cars within reach of each other in either world: a group
    // with no changed car (state or input) steps as it did.
    parent_.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) parent_[i] = i;
    for (const WorldState* w : worlds) join_near(*w, reach, order_, parent_);
    changed_.assign(n, 0);
    for (std::uint32_t i = 0; i < n; ++i) {
        const CarState& c = replay_.cars[i];
        if (!c.active) continue;
        if (!(inputs_[i] == kept.inputs[i]) || !same_car(c, kept.world.cars[i])) changed_[root(parent_, i)] = 1;
    }
    bool any = false;
    for (std::uint32_t i = 0; i < n; ++i) {
        reuse_[i] = replay_.cars[i].active && kept.world.cars[i].active && !changed_[root(parent_, i)];
        any = any || reuse_[i];
    }
    return any;
}

void Predictor::replay_tick(const Scene& scene, const proto::WorldSnapshot& snap, std::size_t own, std::uint32_t t,
                            std::uint32_t target) {
    fill_inputs(snap, own, t, inputs_);
    effective_inputs(replay_, inputs_);
    // Near in the prediction replaced (kept before step_kept overwrites
    // it) or in the replay.
    const char* was_near = near_.find(t);
    near_replay_ = near_replay_ || (was_near != nullptr && *was_near != 0);
    const bool near = near_other_car(scene, replay_, own);  // every car active still
    const bool kept_next = t + 1 == target || holds(t + 1);
    if (!holds(t) || !kept_next || !find_reusable(scene, frame(t))) {
        step_kept(scene, replay_, inputs_, own, near);
        return;
    }
    // The kept next tick (read before step_kept overwrites tick t's frame;
    // tick t + 1's is overwritten only by the next replayed tick).
    const WorldState& next = t + 1 == target ? world_ : frame(t + 1).world;
    const std::size_t n = replay_.cars.size();
    std::uint64_t reused = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (reuse_[i]) replay_.cars[i].active = false;  // the step skips it
    }
    // step_kept keeps tick t's frame with the reused cars inactive: restore them.
    step_kept(scene, replay_, inputs_, own, near);
    Frame& f = *frames_.find(t);  // step_kept just kept it
    for (std::size_t i = 0; i < n; ++i) {
        if (!reuse_[i]) continue;
        f.world.cars[i].active = true;
        replay_.cars[i] = next.cars[i];
        ++reused;
    }
    if (reuse_[own]) my_states_.insert(t, f.world.cars[own]);
    work_.reused_car_steps += reused;
}

}  // namespace jetrace::client}  // namespace jetrace::client
