// import_gltf_bytes() on untrusted glTF JSON or GLB (what import_gltf_file()
// runs on a file's bytes; no external file may be read from memory).
// Invariants: an accepted mesh has whole triangles with finite corners within
// the coordinate limit; it builds a mesh track that keeps every triangle it
// does not drop as degenerate, and building it again gives the same identity.
#include "fuzz_check.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <cmath>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    jetrace::ImportedMesh mesh;
    std::string error;
    if (!jetrace::import_gltf_bytes(bytes, "", mesh, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return 0;
    }
    JETRACE_FUZZ_CHECK(!mesh.parts.empty() && mesh.triangles() <= jetrace::kMaxTrackTriangles);
    for (const jetrace::MeshPart& p : mesh.parts) {
        JETRACE_FUZZ_CHECK(p.corners.size() % 3 == 0 && !p.corners.empty());
        for (const jetrace::Vec3& v : p.corners) {
            JETRACE_FUZZ_CHECK(v.cwiseAbs().maxCoeff() <= jetrace::kMaxTrackCoordinate_m);
        }
    }
    jetrace::TrackManifest m;
    jetrace::Track a, b;
    jetrace::TrackReport ra, rb;
    const bool ok = jetrace::build_mesh_track(m, {mesh}, a, ra, error);
    JETRACE_FUZZ_CHECK(ok || ra.degenerate_dropped == mesh.triangles());
    if (!ok) return 0;
    JETRACE_FUZZ_CHECK(a.triangles.size() + ra.degenerate_dropped == mesh.triangles());
    JETRACE_FUZZ_CHECK(jetrace::build_mesh_track(m, {mesh}, b, rb, error) && a.identity() == b.identity());
    return 0;
}
