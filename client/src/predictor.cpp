#include "jetrace/client/predictor.hpp"

#include "jetrace/car_fields.hpp"

#include <algorithm>
#include <bit>
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

template <class T>
std::uint64_t bits_of(const T& v) {
    if constexpr (std::is_same_v<T, double>) {
        return std::bit_cast<std::uint64_t>(v);
    } else {
        return static_cast<std::uint64_t>(v);
    }
}

bool same_car(const CarState& a, const CarState& b) {
    // Bit for bit, field by field (never the padding): -0 and 0 differ.
    std::array<std::uint64_t, kCarFieldCount> fa{};
    std::size_t n = 0;
    visit_car_fields(a, [&](const char*, const auto& v) { fa[n++] = bits_of(v); });
    n = 0;
    bool same = true;
    visit_car_fields(b, [&](const char*, const auto& v) { same = same && fa[n++] == bits_of(v); });
    return same;
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
    my_input_ticks_.fill(proto::kNoTick);
    my_state_ticks_.fill(proto::kNoTick);
    for (Frame& f : frames_) f.tick = proto::kNoTick;
}

void Predictor::start(const WorldState& w) { world_ = w; }

void Predictor::fill_inputs(const proto::WorldSnapshot& snap, std::size_t own, std::uint32_t t,
                            std::vector<Input>& out) const {
    out.resize(snap.state.cars.size());
    for (std::size_t s = 0; s < out.size(); ++s) out[s] = known_input(snap, s, t);
    if (const Input* mine = my_input(t); mine != nullptr && own < out.size()) out[own] = *mine;
}

void Predictor::step_kept(const Scene& scene, WorldState& w, const std::vector<Input>& inputs, std::size_t own) {
    const std::uint32_t t = w.tick;
    my_states_[t % kRing] = w.cars[own];
    my_state_ticks_[t % kRing] = t;
    Frame& f = frames_[t % kFrames];
    f.tick = t;
    f.world = w;  // reuses the frame's storage
    f.inputs = inputs;
    step(scene, w, inputs, scratch_);
}

void Predictor::run_tick(const Scene& scene, std::size_t own, const Input& mine, const proto::WorldSnapshot& latest) {
    const std::uint32_t t = world_.tick;
    my_inputs_[t % kRing] = mine;
    my_input_ticks_[t % kRing] = t;
    if (thin_) {
        ++world_.tick;
        return;
    }
    fill_inputs(latest, own, t, inputs_);
    inputs_.resize(world_.cars.size());
    step_kept(scene, world_, inputs_, own);
}

std::uint32_t Predictor::first_stale_tick(const proto::WorldSnapshot& snap, std::size_t own, std::uint32_t target) {
    const std::uint32_t S = snap.state.tick;
    if (!holds(S) || !same_world(frames_[S % kFrames].world, snap.state)) return S;
    std::uint32_t t = S;
    while (t < target && holds(t)) {
        fill_inputs(snap, own, t, inputs_);
        if (inputs_ != frames_[t % kFrames].inputs) return t;
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
    if (check_own && my_state_ticks_[S % kRing] == S) {
        const CarState& mine = my_states_[S % kRing];
        if (car_hash(mine) != car_hash(snap.state.cars[own])) {
            o.corrected = true;
            o.error_m = (mine.position - snap.state.cars[own].position).norm();
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
    replay_ = from == S ? snap.state : frames_[from % kFrames].world;
    for (std::uint32_t t = from; t < target; ++t) {
        fill_inputs(snap, own, t, inputs_);
        step_kept(scene, replay_, inputs_, own);
    }
    std::swap(world_, replay_);  // both keep their storage
    work_.replayed_ticks += target - from;
    return o;
}

}  // namespace jetrace::client
