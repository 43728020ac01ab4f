// A track from a manifest and its meshes: parts chosen by name, the up axis
// turned to Y and scaled, zero-area triangles dropped (counted and reported),
// then gates and spawns placed (route_gates.cpp). Triangles keep file order:
// mesh by mesh, part by part, triangle by triangle.
#include "jetrace/tracks/track_io.hpp"
#include "jetrace/tracks/track_manifest.hpp"

#include "route_gates.hpp"

#include <fnmatch.h>

#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>

namespace jetrace {
namespace {

bool fail(std::string& error, std::string message) {
    error = std::move(message);
    return false;
}

bool matches(const std::vector<std::string>& patterns, const std::string& name) {
    for (const std::string& p : patterns) {
        if (::fnmatch(p.c_str(), name.c_str(), 0) == 0) return true;
    }
    return false;
}

Vec3 to_track(const TrackManifest& m, const Vec3& p) {
    const Vec3 y_up = m.up == 'z' ? Vec3(p.x(), p.z(), -p.y()) : p;
    return y_up * m.scale;
}

struct Assembly {
    std::vector<Vec3> corners;
    std::vector<std::pair<std::size_t, std::string>> parts;  // (end triangle, name)
    std::size_t degenerate = 0;
    std::string first_degenerate;
};

bool assemble(const TrackManifest& m, const std::vector<ImportedMesh>& meshes, Assembly& a, TrackReport& report,
              std::string& error) {
    std::string names;
    for (const ImportedMesh& mesh : meshes) {
        report.skipped_primitives += mesh.skipped_primitives;
        for (const MeshPart& part : mesh.parts) {
            const std::size_t n = part.corners.size() / 3;
            report.source_triangles += n;
            if (names.size() < 400) names += (names.empty() ? "'" : ", '") + part.name + "'";
            if (!matches(m.drivable, part.name) || matches(m.ignore, part.name)) {
                report.ignored_triangles += n;
                continue;
            }
            for (std::size_t i = 0; i < n; ++i) {
                const Vec3 p0 = to_track(m, part.corners[3 * i]), p1 = to_track(m, part.corners[3 * i + 1]),
                           p2 = to_track(m, part.corners[3 * i + 2]);
                if (Triangle::make(p0, p1, p2).degenerate) {
                    if (a.degenerate++ == 0) a.first_degenerate = "'" + part.name + "' at " + detail::where(p0);
                    continue;
                }
                a.corners.insert(a.corners.end(), {p0, p1, p2});
            }
            if (a.corners.size() / 3 > kMaxTrackTriangles) {
                return fail(error, "more than " + std::to_string(kMaxTrackTriangles) + " drivable triangles");
            }
            if (a.parts.empty() || a.parts.back().first != a.corners.size() / 3) {
                a.parts.emplace_back(a.corners.size() / 3, part.name);
            }
        }
    }
    report.degenerate_dropped = a.degenerate;  // also when nothing else is left
    if (a.corners.empty()) return fail(error, "no drivable triangles: 'drivable'/'ignore' leave none of the parts (" + names + ")");
    for (const Vec3& p : a.corners) {
        if (!(p.cwiseAbs().maxCoeff() <= kMaxTrackCoordinate_m)) return fail(error, "a vertex lies beyond 1e6 m after 'scale'");
    }
    if (a.degenerate > 0) {
        report.warnings.push_back(std::to_string(a.degenerate) + " degenerate (zero-area) triangles dropped (the first in " +
                                  a.first_degenerate + ")");
    }
    return true;
}

bool read_file(const std::string& path, std::size_t limit, std::string& text, std::string& error) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return fail(error, "cannot open '" + path + "' (no such regular file)");
    const auto size = std::filesystem::file_size(path, ec);
    if (ec || size > limit) return fail(error, "'" + path + "' is larger than " + std::to_string(limit) + " bytes");
    std::ifstream in(path, std::ios::binary);
    std::ostringstream buf;
    buf << in.rdbuf();
    if (!in) return fail(error, "cannot read '" + path + "'");
    text = buf.str();
    return true;
}

bool ends_with(const std::string& s, std::string_view tail) { return s.size() >= tail.size() && s.ends_with(tail); }

}  // namespace

bool import_mesh_file(const std::string& path, ImportedMesh& out, std::string& error) {
    if (ends_with(path, ".gltf") || ends_with(path, ".glb")) return import_gltf_file(path, out, error);
    if (!ends_with(path, ".obj")) return fail(error, "'" + path + "': a mesh must end in .gltf, .glb or .obj");
    std::string text;
    if (!read_file(path, kMaxTrackFileBytes, text, error)) return false;
    if (!import_obj_mesh(text, out, error)) return fail(error, path + ": " + error);
    return true;
}

namespace {

bool mesh_track(const TrackManifest& m, const std::vector<ImportedMesh>& meshes, Track& track, Assembly& a,
                TrackReport& report, std::string& error) {
    if (!assemble(m, meshes, a, report, error)) return false;
    std::vector<std::uint32_t> idx(a.corners.size());
    std::iota(idx.begin(), idx.end(), 0u);
    track = make_track(m.name, a.corners, idx, {}, {}, 0.0);
    track.kill_height_m = m.kill_height_m.value_or(track.bounds.min.y() - 50.0);
    return true;
}

}  // namespace

bool build_mesh_track(const TrackManifest& m, const std::vector<ImportedMesh>& meshes, Track& out,
                      TrackReport& report, std::string& error) {
    Assembly a;
    return mesh_track(m, meshes, out, a, report, error);
}

bool build_manifest_track(const TrackManifest& m, const std::vector<ImportedMesh>& meshes, Track& out,
                          TrackReport& report, std::string& error) {
    report.format = "manifest";
    Assembly a;
    Track track;
    if (!mesh_track(m, meshes, track, a, report, error)) return false;
    detail::Surface surface{track.triangles, std::move(a.parts), track.bounds, m.route_surface};
    if (!detail::place_gates_and_spawns(m, surface, track, report, error)) return false;
    if (std::string problem = validate(track); !problem.empty()) return fail(error, std::move(problem));
    out = std::move(track);
    return true;
}

bool load_manifest_file(const std::string& path, Track& out, TrackReport& report, std::string& error) {
    std::string text;
    if (!read_file(path, kMaxManifestBytes, text, error)) return false;
    TrackManifest m;
    const std::string dir = std::filesystem::path(path).parent_path().string();
    if (!parse_manifest(text, dir.empty() ? "." : dir, m, error)) return fail(error, path + ": " + error);
    if (m.name.empty()) {
        m.name = std::filesystem::path(path).filename().string();
        m.name = m.name.substr(0, m.name.find('.'));
    }
    std::vector<ImportedMesh> meshes(m.meshes.size());
    for (std::size_t i = 0; i < m.meshes.size(); ++i) {
        if (!import_mesh_file(m.meshes[i], meshes[i], error)) return false;
    }
    if (!build_manifest_track(m, meshes, out, report, error)) return fail(error, path + ": " + error);
    return true;
}

}  // namespace jetrace
