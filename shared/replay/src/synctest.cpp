#include "jetrace/replay/synctest.hpp"

#include <cassert>
#include <deque>

namespace jetrace::replay {

namespace {

void apply(const Scene& scene, WorldState& st, const TickRecord& t, StepScratch& scratch) {
    for (std::uint8_t s : t.removed) remove_car(st, s);
    step(scene, st, t.inputs, scratch);
}

class SyncTest {
public:
    SyncTest(const SceneFor& scene_for, int rollback) : scene_for_(scene_for) { r_.rollback_ticks = rollback; }

    SynctestReport run(ByteSource& source) {
        Scanner scanner(source);
        Event ev;
        bool going = true;
        while (going && scanner.next(ev)) {
            if (ev.kind == RecordKind::header) going = header(ev.header);
            if (ev.kind == RecordKind::tick) going = tick(ev.tick);
        }
        if (going && !scanner.ok() && scanner.failure().problem != Problem::incomplete) {
            fail("replay", scanner.failure().message);
        }
        r_.ok = r_.check.empty();
        return r_;
    }

private:
    bool fail(const char* check, std::string message) {
        r_.check = check;
        r_.tick = state_.tick;
        r_.message = std::move(message);
        return false;
    }

    bool header(const Header& h) {
        std::string error;
        scene_ = scene_for_(h, error);
        if (!scene_) return fail("replay", error);
        state_ = h.initial;
        return true;
    }

    bool tick(const TickRecord& t) {
        WorldState again = state_;
        history_.push_back({state_, t});
        if (history_.size() > static_cast<std::size_t>(r_.rollback_ticks)) history_.pop_front();
        apply(*scene_, state_, t, scratch_);
        ++r_.ticks;
        StepScratch fresh;
        apply(*scene_, again, t, fresh);
        ++r_.fresh_checks;
        if (!same_state(state_, again)) {
            r_.fields = diff_states(state_, again);
            return fail("fresh_scratch", "stepping the saved state again with fresh scratch gives another world");
        }
        if (history_.size() == static_cast<std::size_t>(r_.rollback_ticks) && r_.ticks % r_.rollback_ticks == 0) {
            return rollback();
        }
        return true;
    }

    bool rollback() {
        WorldState st = history_.front().first;
        for (const auto& [saved, t] : history_) apply(*scene_, st, t, scratch_);
        ++r_.rollback_checks;
        if (same_state(state_, st)) return true;
        r_.fields = diff_states(state_, st);
        return fail("rollback", "re-simulating the last " + std::to_string(r_.rollback_ticks) +
                                    " ticks from a saved state with the live scratch gives another world");
    }

    const SceneFor& scene_for_;
    const Scene* scene_ = nullptr;
    WorldState state_;
    StepScratch scratch_;
    std::deque<std::pair<WorldState, TickRecord>> history_;
    SynctestReport r_;
};

}  // namespace

SynctestReport synctest(ByteSource& source, const SceneFor& scene_for, int rollback_ticks) {
    assert(rollback_ticks >= 1 && rollback_ticks <= 240);
    return SyncTest(scene_for, rollback_ticks).run(source);
}

}  // namespace jetrace::replay
