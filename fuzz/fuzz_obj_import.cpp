// import_obj() on untrusted OBJ text (the in-memory entry point that
// import_obj_file() and load_track() use). Invariants: an accepted track
// validates; export_obj() of it imports again with the same triangles bit
// for bit and the same gate and spawn counts; and, as the server and
// jetrace-sim do next, a scene builds on it and a car spawned on it steps.
#include "fuzz_check.hpp"
#include "jetrace/core/world.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <bit>
#include <string_view>

namespace {

bool same_vec(const jetrace::Vec3& a, const jetrace::Vec3& b) {
    for (int i = 0; i < 3; ++i)
        if (std::bit_cast<std::uint64_t>(a[i]) != std::bit_cast<std::uint64_t>(b[i])) return false;
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    jetrace::Track track;
    std::string error;
    if (!jetrace::import_obj(text, "fuzz", track, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    JETRACE_FUZZ_CHECK(jetrace::validate(track).empty());

    jetrace::Track again;
    JETRACE_FUZZ_CHECK(jetrace::import_obj(jetrace::export_obj(track), "fuzz", again, error));
    JETRACE_FUZZ_CHECK(again.triangles.size() == track.triangles.size());
    for (std::size_t i = 0; i < track.triangles.size(); ++i) {
        const jetrace::Triangle &a = track.triangles[i], &b = again.triangles[i];
        JETRACE_FUZZ_CHECK(same_vec(a.a, b.a) && same_vec(a.b, b.b) && same_vec(a.c, b.c));
    }
    JETRACE_FUZZ_CHECK(again.checkpoints.size() == track.checkpoints.size() &&
                       again.spawns.size() == track.spawns.size());

    const jetrace::PhysicsSettings physics;
    const jetrace::Scene scene = jetrace::Scene::make(std::move(track), physics);
    jetrace::World world(scene, jetrace::make_world(1, 1));
    jetrace::spawn_car(scene, world.state(), 0, 0);
    const jetrace::Input full = jetrace::Input::clamped(jetrace::Input::kMaxThrottle, 0, 0);
    for (int i = 0; i < 4; ++i) world.step(std::span(&full, 1));
    return 0;
}
