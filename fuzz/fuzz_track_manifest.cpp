// parse_manifest() on untrusted JSON, then build_manifest_track() on a fixed
// mesh (a 200 m floor with a wall and a low bridge) for each mesh it names:
// routes, explicit gates, spacing, spawns and every check. Invariants: an
// accepted track validates, has the gates and spawns asked for, and builds
// again with the same identity.
#include "fuzz_check.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <string_view>

namespace {

jetrace::ImportedMesh level() {
    jetrace::ImportedMesh m;
    m.parts.push_back({"Floor", {{-100, 0, -100}, {-100, 0, 100}, {100, 0, 100}, {-100, 0, -100}, {100, 0, 100},
                                 {100, 0, -100}}});
    m.parts.push_back({"Wall", {{-100, 0, 30}, {100, 0, 30}, {100, 20, 30}}});
    m.parts.push_back({"Bridge", {{-10, 4, -10}, {-10, 4, 10}, {10, 4, 10}}});
    return m;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    jetrace::TrackManifest m;
    std::string error;
    if (!jetrace::parse_manifest(text, "/nonexistent", m, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    JETRACE_FUZZ_CHECK(!m.meshes.empty() && (!m.route.empty() || m.gates.size() >= 2));
    if (m.meshes.size() > 4) return 0;  // each copy is the whole level: keep runs short
    const std::vector<jetrace::ImportedMesh> meshes(m.meshes.size(), level());
    jetrace::Track a, b;
    jetrace::TrackReport ra, rb;
    if (!jetrace::build_manifest_track(m, meshes, a, ra, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    JETRACE_FUZZ_CHECK(jetrace::validate(a).empty());
    JETRACE_FUZZ_CHECK(a.spawns.size() == static_cast<std::size_t>(m.spawn_count));
    JETRACE_FUZZ_CHECK(m.gates.empty() || a.checkpoints.size() == m.gates.size());
    JETRACE_FUZZ_CHECK(jetrace::build_manifest_track(m, meshes, b, rb, error) && a.identity() == b.identity());
    return 0;
}
