// The replay reader on untrusted bytes (what jetrace-sim --verify reads from
// a file): the Scanner alone, then verify() and synctest() on the built-in
// "ring" with default physics (the seed corpus is recorded there), as
// jetrace-sim does. Invariants: every record the scanner hands out is in
// sequence (ticks consecutive from the initial tick, one input per slot,
// removed slots in range, checkpoints and keyframes at their tick); a clean
// end means the trailer was read; every failure has a reason; a verdict is
// ok exactly when it names no problem, and then the replay was complete.
#include "fuzz_check.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/replay/synctest.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

namespace {

const jetrace::replay::SceneFor& ring() {
    static const jetrace::replay::SceneFor scenes = jetrace::replay::scene_for(jetrace::load_builtin, "ring");
    return scenes;
}

void scan(std::span<const std::uint8_t> bytes) {
    using namespace jetrace::replay;
    SpanSource src(bytes);
    Scanner sc(src);
    Event ev;
    bool header = false;
    std::size_t slots = 0;
    std::uint32_t tick = 0;
    while (sc.next(ev)) {
        JETRACE_FUZZ_CHECK(header == (ev.kind != RecordKind::header));
        if (ev.kind == RecordKind::header) {
            header = true;
            slots = ev.header.initial.cars.size();
            tick = ev.header.initial.tick;
        } else if (ev.kind == RecordKind::tick) {
            JETRACE_FUZZ_CHECK(ev.tick.tick == tick++ && ev.tick.inputs.size() == slots);
            for (std::uint8_t s : ev.tick.removed) JETRACE_FUZZ_CHECK(s < slots);
        } else if (ev.kind == RecordKind::checkpoint) {
            JETRACE_FUZZ_CHECK(ev.checkpoint.tick == tick && ev.checkpoint.car_hashes.size() == slots);
        } else if (ev.kind == RecordKind::keyframe) {
            JETRACE_FUZZ_CHECK(ev.keyframe.tick == tick && ev.keyframe.cars.size() == slots);
        }
        JETRACE_FUZZ_CHECK(sc.tick() == tick);
    }
    JETRACE_FUZZ_CHECK(sc.ok() ? sc.complete() : !sc.failure().message.empty());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace jetrace::replay;
    const auto bytes = jetrace::fuzz::bytes(data, size);
    scan(bytes);
    SpanSource a(bytes);
    const Verdict v = verify(a, ring());
    JETRACE_FUZZ_CHECK(v.ok == v.problem.empty());
    JETRACE_FUZZ_CHECK(!v.ok || v.complete);
    JETRACE_FUZZ_CHECK(v.ok || !v.message.empty());
    SpanSource b(bytes);
    const SynctestReport r = synctest(b, ring(), 4);
    JETRACE_FUZZ_CHECK(r.ok == r.check.empty());
    return 0;
}
