#include "jetrace/replay/diff.hpp"

#include "jetrace/core/state_bytes.hpp"

#include <deque>

namespace jetrace::replay {

namespace {

/// Tick records kept for re-simulating from the last agreeing keyframe
/// (about 23 minutes at 120 Hz; more means no keyframes: not re-simulated).
constexpr std::size_t kMaxBufferedTicks = 1u << 17;

struct Side {
    explicit Side(ByteSource& s) : scanner(s) {}
    Scanner scanner;
    Event ev;
    Header header;
    std::optional<TickRecord> next_tick;
    std::deque<Checkpoint> checkpoints;
    std::optional<WorldState> keyframe;
    std::optional<Trailer> trailer;

    bool read_header() {
        if (!scanner.next(ev)) return false;
        header = ev.header;
        return true;
    }
    /// Reads on to the next tick record (kept in next_tick; none at the
    /// end), gathering the checkpoints and keyframes on the way.
    void fill() {
        next_tick.reset();
        while (scanner.next(ev)) {
            if (ev.kind == RecordKind::tick) {
                next_tick = std::move(ev.tick);
                return;
            }
            if (ev.kind == RecordKind::checkpoint) checkpoints.push_back(ev.checkpoint);
            if (ev.kind == RecordKind::keyframe) keyframe = ev.keyframe;
            if (ev.kind == RecordKind::trailer) trailer = ev.trailer;
        }
    }
    bool keyframe_at(std::uint32_t tick) const { return keyframe && keyframe->tick == tick; }
};

std::string header_difference(const Header& a, const Header& b) {
    if (a.track_identity != b.track_identity) return "they were recorded on different tracks";
    if (a.physics_hash != b.physics_hash || a.tick_rate_hz != b.tick_rate_hz) return "their physics settings differ";
    if (!same_state(a.initial, b.initial)) return "their initial worlds differ";
    return {};
}

class Differ {
public:
    Differ(ByteSource& a, ByteSource& b, const SceneFor& scene_for, std::size_t max_fields)
        : a_(a), b_(b), scene_for_(scene_for), max_fields_(max_fields) {}

    DiffReport run() {
        if (!a_.read_header() || !b_.read_header()) return unreadable();
        if (const std::string d = header_difference(a_.header, b_.header); !d.empty()) {
            r_.verdict = "different_races";
            r_.message = "not two recordings of one race: " + d;
            return r_;
        }
        base_ = a_.header.initial;
        a_.fill();
        b_.fill();
        while (!compare_checkpoints() && a_.next_tick && b_.next_tick) {
            if (!same_inputs(*a_.next_tick, *b_.next_tick)) return r_;
            if (buffered_.size() < kMaxBufferedTicks) buffered_.push_back(*a_.next_tick);
            ++r_.ticks_compared;
            a_.fill();
            b_.fill();
        }
        if (r_.first_differing_tick) return locate();
        return ended();
    }

private:
    DiffReport unreadable() {
        r_.verdict = "unreadable";
        const Scanner& bad = a_.scanner.ok() ? b_.scanner : a_.scanner;
        r_.message = std::string(a_.scanner.ok() ? "B" : "A") + ": " + bad.failure().message;
        return r_;
    }

    bool same_inputs(const TickRecord& x, const TickRecord& y) {
        if (x.removed != y.removed) {
            r_.verdict = "inputs_differ";
            r_.input_tick = x.tick;
            r_.message = "the cars removed before tick " + std::to_string(x.tick) + " differ";
            return false;
        }
        for (std::size_t s = 0; s < x.inputs.size(); ++s) {
            if (x.inputs[s].pack() == y.inputs[s].pack()) continue;
            r_.verdict = "inputs_differ";
            r_.input_tick = x.tick;
            r_.input_slot = static_cast<int>(s);
            r_.input_a = x.inputs[s].pack();
            r_.input_b = y.inputs[s].pack();
            r_.message = "the inputs of slot " + std::to_string(s) + " differ at tick " + std::to_string(x.tick) +
                         ": these are recordings of different races, not a desync";
            return false;
        }
        return true;
    }

    /// Compares the checkpoints both sides have for the same tick; true at
    /// the first that differs.
    bool compare_checkpoints() {
        auto& qa = a_.checkpoints;
        auto& qb = b_.checkpoints;
        while (!qa.empty() && !qb.empty()) {
            if (qa.front().tick != qb.front().tick) {
                (qa.front().tick < qb.front().tick ? qa : qb).pop_front();
                continue;
            }
            const Checkpoint& ca = qa.front();
            const Checkpoint& cb = qb.front();
            if (ca.state_hash != cb.state_hash || ca.car_hashes != cb.car_hashes) {
                r_.first_differing_tick = ca.tick;
                r_.cars = differing_cars(ca, cb);
                at_a_ = ca;
                at_b_ = cb;
                return true;
            }
            r_.last_agreeing_tick = ca.tick;
            if (a_.keyframe_at(ca.tick) || b_.keyframe_at(ca.tick)) {
                base_ = a_.keyframe_at(ca.tick) ? *a_.keyframe : *b_.keyframe;
                buffered_.clear();
            }
            qa.pop_front();
            qb.pop_front();
        }
        return false;
    }

    DiffReport locate() {
        const std::uint32_t d = *r_.first_differing_tick;
        while (!(a_.keyframe && a_.keyframe->tick >= d) && a_.next_tick) a_.fill();
        while (!(b_.keyframe && b_.keyframe->tick >= d) && b_.next_tick) b_.fill();
        if (a_.keyframe && b_.keyframe && a_.keyframe->tick >= d && a_.keyframe->tick == b_.keyframe->tick) {
            r_.fields_tick = a_.keyframe->tick;
            r_.fields = diff_states(*a_.keyframe, *b_.keyframe, max_fields_);
        }
        rebuild(d);
        r_.verdict = "desync";
        r_.message = "the recordings agree up to " +
                     (r_.last_agreeing_tick ? "tick " + std::to_string(*r_.last_agreeing_tick) : std::string("the start")) +
                     " and differ at tick " + std::to_string(d) + " with the same inputs";
        return r_;
    }

    /// Re-simulates from the last agreeing keyframe to tick d with this build.
    void rebuild(std::uint32_t d) {
        std::string error;
        const Scene* scene = scene_for_(a_.header, error);
        const bool all_there = buffered_.size() < kMaxBufferedTicks;
        if (!scene || !all_there || scene->track.identity() != a_.header.track_identity) return;
        WorldState st = base_;
        StepScratch scratch;
        for (const TickRecord& t : buffered_) {
            if (st.tick >= d) break;
            for (std::uint8_t s : t.removed) remove_car(st, s);
            step(*scene, st, t.inputs, scratch);
        }
        const Checkpoint mine = checkpoint_of(st);
        const auto same = [&](const Checkpoint& c) { return c.state_hash == mine.state_hash && c.car_hashes == mine.car_hashes; };
        r_.this_build = same(at_a_) ? "a" : same(at_b_) ? "b" : "neither";
    }

    DiffReport ended() {
        if (!a_.scanner.ok() || !b_.scanner.ok()) return unreadable();
        const bool both = a_.trailer && b_.trailer;
        if (both && a_.trailer->final_state_hash == b_.trailer->final_state_hash && !a_.next_tick && !b_.next_tick) {
            r_.verdict = "identical";
            r_.message = "the recordings agree at every common checkpoint and end alike";
            return r_;
        }
        r_.verdict = "shorter";
        r_.message = std::string(a_.next_tick ? "B" : "A") + " ends first, after " + std::to_string(r_.ticks_compared) +
                     " common ticks; they agree up to there";
        return r_;
    }

    Side a_, b_;
    const SceneFor& scene_for_;
    std::size_t max_fields_;
    DiffReport r_;
    WorldState base_;
    std::vector<TickRecord> buffered_;
    Checkpoint at_a_, at_b_;
};

}  // namespace

DiffReport diff_replays(ByteSource& a, ByteSource& b, const SceneFor& scene_for, std::size_t max_fields) {
    return Differ(a, b, scene_for, max_fields).run();
}

DiffReport diff_against_build(const Verdict& v) {
    DiffReport r;
    r.ticks_compared = v.final_tick - v.initial_tick;
    r.last_agreeing_tick = v.last_good_checkpoint;
    if (v.ok) {
        r.verdict = "identical";
        r.message = "this build re-simulates the recording exactly";
        return r;
    }
    const bool desync = v.problem == "checkpoint_mismatch" || v.problem == "keyframe_mismatch" ||
                        v.problem == "final_hash_mismatch";
    r.verdict = desync ? "desync" : "unreadable";
    r.message = v.message;
    if (desync) {
        r.first_differing_tick = v.tick;
        r.cars = v.cars;
        r.fields_tick = v.fields_tick;
        r.fields = v.fields;
    }
    return r;
}

}  // namespace jetrace::replay
