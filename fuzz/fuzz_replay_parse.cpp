// parse_replay() on untrusted replay bytes (what read_replay() reads from a
// file), then what jetrace-sim --replay does with an accepted replay:
// check_replay() against the scene it names (built-in "ring", default
// physics: the seed corpus is recorded there) and, if that accepts it,
// run_replay() over its first kMaxTicks ticks. Invariants: an accepted
// replay's records are in sequence with one input per slot and removed
// slots in range; a checked replay re-simulates without a crash or UB.
#include "fuzz_check.hpp"
#include "jetrace/builtin_tracks.hpp"
#include "jetrace/server/replay.hpp"
#include "jetrace/world.hpp"

namespace {

/// Ticks re-simulated per input (bounds the time per run).
constexpr std::size_t kMaxTicks = 64;

const jetrace::Scene& ring_scene() {
    static const jetrace::Scene scene = [] {
        jetrace::Track track;
        const bool built = jetrace::make_builtin_track("ring", track);
        JETRACE_FUZZ_CHECK(built);
        return jetrace::Scene::make(std::move(track), jetrace::PhysicsSettings{});
    }();
    return scene;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    jetrace::Replay replay;
    std::string error;
    if (!jetrace::parse_replay(jetrace::fuzz::bytes(data, size), replay, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    const std::size_t slots = replay.header.initial.cars.size();
    std::uint32_t expected = replay.header.initial.tick;
    for (const jetrace::ReplayTick& t : replay.ticks) {
        JETRACE_FUZZ_CHECK(t.tick == expected++ && t.inputs.size() == slots);
        for (std::uint8_t s : t.removed) JETRACE_FUZZ_CHECK(s < slots);
    }
    const jetrace::Scene& scene = ring_scene();
    if (!jetrace::check_replay(scene, replay, jetrace::physics_fingerprint(scene.physics), error)) return 0;
    if (replay.ticks.size() > kMaxTicks) replay.ticks.resize(kMaxTicks);
    const jetrace::WorldState final_state = jetrace::run_replay(scene, replay);
    JETRACE_FUZZ_CHECK(final_state.cars.size() == slots);
    return 0;
}
