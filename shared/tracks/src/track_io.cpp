#include "jetrace/tracks/track_io.hpp"

#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/jtrack.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace jetrace {
namespace {

bool ends_with(const std::string& s, std::string_view tail) { return s.ends_with(tail); }
bool is_gltf(const std::string& s) { return ends_with(s, ".gltf") || ends_with(s, ".glb"); }

std::size_t degenerate_count(const Track& t) {
    std::size_t n = 0;
    for (const Triangle& tri : t.triangles) n += tri.degenerate ? 1 : 0;
    return n;
}

// The triangles-only report of a track loaded without a manifest.
void plain_report(const Track& t, const char* format, TrackReport& report) {
    report = TrackReport{};
    report.format = format;
    report.source_triangles = t.triangles.size();
}

}  // namespace

bool import_obj_file(const std::string& path, Track& out, std::string& error) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        error = "cannot open track file '" + path + "' (no such regular file)";
        return false;
    }
    if (const auto size = std::filesystem::file_size(path, ec); ec || size > kMaxTrackFileBytes) {
        error = "track file '" + path + "' is larger than " + std::to_string(kMaxTrackFileBytes) + " bytes";
        return false;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = "cannot open track file '" + path + "'";
        return false;
    }
    std::ostringstream buf;
    buf << in.rdbuf();
    if (in.bad()) {
        error = "cannot read track file '" + path + "'";
        return false;
    }
    std::string name = path;
    const auto slash = name.find_last_of('/');
    if (slash != std::string::npos) name = name.substr(slash + 1);
    if (name.size() > 4 && name.substr(name.size() - 4) == ".obj") name.resize(name.size() - 4);
    if (!import_obj(buf.str(), name, out, error)) {
        error = path + ": " + error;
        return false;
    }
    return true;
}

bool load_track_report(const std::string& spec, Track& out, TrackReport& report, std::string& error) {
    if (make_builtin_track(spec, out)) {
        plain_report(out, "builtin", report);
        return true;
    }
    // A compiled track by its extension or, under any name, by its magic.
    if (ends_with(spec, ".jtrack") || file_is_jtrack(spec)) {
        if (!load_jtrack_file(spec, out, error)) return false;
        plain_report(out, "jtrack", report);
        return true;
    }
    if (ends_with(spec, ".obj")) {
        if (!import_obj_file(spec, out, error)) return false;
        plain_report(out, "obj", report);
        // The OBJ convention keeps every triangle (the track's identity is its file's).
        if (const std::size_t d = degenerate_count(out); d > 0) {
            report.warnings.push_back(std::to_string(d) + " degenerate (zero-area) triangles (kept: the OBJ convention)");
        }
        return true;
    }
    if (ends_with(spec, ".json")) {
        report = TrackReport{};
        return load_manifest_file(spec, out, report, error);
    }
    if (is_gltf(spec)) {
        error = "'" + spec + "' is a mesh without gates or spawns: describe it in a track manifest (.track.json, "
                "docs/TRACKS.md)";
        return false;
    }
    error = "unknown track '" + spec + "': use a built-in name (";
    const auto names = builtin_track_names();
    for (std::size_t i = 0; i < names.size(); ++i) error += (i ? ", " : "") + names[i];
    error += "), a path ending in .obj, a track manifest (.json) or a compiled track (.jtrack)";
    return false;
}

bool load_track(const std::string& spec, Track& out, std::string& error) {
    TrackReport report;
    return load_track_report(spec, out, report, error);
}

bool inspect_track(const std::string& spec, Track& out, TrackReport& report, std::string& error) {
    if (!is_gltf(spec)) return load_track_report(spec, out, report, error);
    ImportedMesh mesh;
    if (!import_gltf_file(spec, mesh, error)) return false;
    TrackManifest m;
    m.name = std::filesystem::path(spec).stem().string();
    report = TrackReport{};
    report.format = "gltf";
    return build_mesh_track(m, {mesh}, out, report, error);
}

}  // namespace jetrace
