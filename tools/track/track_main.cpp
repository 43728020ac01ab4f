// jetrace-track: what a track file makes, before racing on it.
//   jetrace-track inspect TRACK [--json]      triangles, degenerate dropped, bounds, gates, spawns, route, warnings
//   jetrace-track render TRACK --svg OUT.svg  a top-down picture: mesh, route, numbered gates, spawns
//   jetrace-track build TRACK --out OUT.jtrack  the compiled track (read back and checked: same identity)
// TRACK: a built-in name, an .obj file, a .gltf/.glb mesh, a track manifest
// (.json) or a compiled track (.jtrack). docs/TRACKS.md, "jetrace-track".
#include "jetrace/tracks/drivability.hpp"
#include "jetrace/tracks/jtrack.hpp"
#include "jetrace/tracks/track_io.hpp"
#include "track_svg.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace {

using nlohmann::json;

json vec(const jetrace::Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

std::string hex_identity(const jetrace::Track& t);

// The drivability warnings (docs/TRACKS.md, "Drivability warnings"): kind,
// subject ("gate", "spawn", "respawn", "track"), its index, where, message.
json drivability(const jetrace::Track& t) {
    json out = json::array();
    for (const jetrace::DrivabilityWarning& w : jetrace::check_drivability(t)) {
        out.push_back({{"kind", w.kind},
                       {"subject", w.subject},
                       {"index", w.index},
                       {"position", vec(w.position)},
                       {"message", w.message}});
    }
    return out;
}

json summary(const jetrace::Track& t, const jetrace::TrackReport& r, double load_ms) {
    const std::string id = hex_identity(t);
    return {{"drivability", drivability(t)},
            {"name", t.name},
            {"format", r.format},
            {"triangles", t.triangles.size()},
            {"source_triangles", r.source_triangles},
            {"degenerate_dropped", r.degenerate_dropped},
            {"ignored_triangles", r.ignored_triangles},
            {"skipped_primitives", r.skipped_primitives},
            {"bounds", {{"min", vec(t.bounds.min)}, {"max", vec(t.bounds.max)}}},
            {"gates", t.checkpoints.size()},
            {"spawns", t.spawns.size()},
            {"route_length_m", r.route_length_m},
            {"kill_height_m", t.kill_height_m},
            {"raceable", jetrace::validate(t).empty()},
            {"identity", id},
            {"load_ms", load_ms},
            {"warnings", r.warnings}};
}

void print_text(const json& s) {
    std::printf("track      %s (%s)\n", s["name"].get<std::string>().c_str(), s["format"].get<std::string>().c_str());
    std::printf("triangles  %zu (source %zu, degenerate dropped %zu, ignored %zu; primitives skipped %zu)\n",
                s["triangles"].get<std::size_t>(), s["source_triangles"].get<std::size_t>(),
                s["degenerate_dropped"].get<std::size_t>(), s["ignored_triangles"].get<std::size_t>(),
                s["skipped_primitives"].get<std::size_t>());
    std::printf("bounds     %s to %s m\n", s["bounds"]["min"].dump().c_str(), s["bounds"]["max"].dump().c_str());
    std::printf("gates      %zu\nspawns     %zu\n", s["gates"].get<std::size_t>(), s["spawns"].get<std::size_t>());
    std::printf("route      %.1f m\nkill       %.1f m\n", s["route_length_m"].get<double>(),
                s["kill_height_m"].get<double>());
    std::printf("raceable   %s\nidentity   %s\nload       %.1f ms\n", s["raceable"].get<bool>() ? "yes" : "no",
                s["identity"].get<std::string>().c_str(), s["load_ms"].get<double>());
    std::printf("warnings   %zu\n", s["warnings"].size() + s["drivability"].size());
    for (const json& w : s["warnings"]) std::printf("  - %s\n", w.get<std::string>().c_str());
    for (const json& w : s["drivability"]) {
        std::printf("  - [%s] %s\n", w["kind"].get<std::string>().c_str(), w["message"].get<std::string>().c_str());
    }
}

int fail(const std::string& message) {
    std::fprintf(stderr, "jetrace-track: %s\n", message.c_str());
    return 1;
}

bool load(const std::string& spec, jetrace::Track& t, jetrace::TrackReport& r, double& ms, std::string& error) {
    const auto start = std::chrono::steady_clock::now();
    const bool ok = jetrace::inspect_track(spec, t, r, error);
    ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return ok;
}

std::string hex_identity(const jetrace::Track& t) {
    char id[17];
    std::snprintf(id, sizeof id, "%016llx", static_cast<unsigned long long>(t.identity()));
    return id;
}

// Loads a raceable track, writes it compiled, reads the file back and checks
// that it is the same track (identity). One JSON line on success.
int build(const std::string& spec, const std::string& out_path) {
    jetrace::Track track;
    std::string error;
    if (!jetrace::load_track(spec, track, error)) return fail(error);
    if (const std::string bad = jetrace::validate(track); !bad.empty()) return fail(spec + ": " + bad);
    if (!jetrace::write_jtrack_file(track, out_path, error)) return fail(error);
    jetrace::Track back;
    if (!jetrace::load_jtrack_file(out_path, back, error)) return fail("reading back: " + error);
    if (back.identity() != track.identity()) return fail(out_path + ": read back with a different identity");
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(out_path, ec);
    const json line = {{"track", track.name},   {"out", out_path},
                       {"triangles", track.triangles.size()}, {"gates", track.checkpoints.size()},
                       {"spawns", track.spawns.size()},       {"bytes", ec ? 0 : bytes},
                       {"identity", hex_identity(track)}};
    std::printf("%s\n", line.dump().c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-track: inspect, render and compile tracks (built-in, OBJ, glTF, a track manifest or .jtrack)"};
    app.require_subcommand(1);
    std::string spec;
    bool as_json = false;
    auto* inspect = app.add_subcommand("inspect", "triangles, degenerate dropped, bounds, gates, spawns, route, warnings");
    inspect->add_option("track", spec, "built-in name, .obj, .gltf, .glb or manifest (.json)")->required();
    inspect->add_flag("--json", as_json, "one JSON object instead of text");
    auto* render = app.add_subcommand("render", "a top-down SVG: mesh, route, numbered gates with arrows, spawns");
    std::string svg_path;
    int width_px = 1200;
    render->add_option("track", spec, "built-in name, .obj, .gltf, .glb or manifest (.json)")->required();
    render->add_option("--svg", svg_path, "the SVG file to write")->required();
    render->add_option("--width", width_px, "picture width in pixels (200..8000)")->check(CLI::Range(200, 8000));
    auto* compile = app.add_subcommand("build", "compile a raceable track into a .jtrack file (docs/TRACKS.md)");
    std::string out_path;
    compile->add_option("track", spec, "built-in name, .obj, manifest (.json) or .jtrack")->required();
    compile->add_option("--out", out_path, "the .jtrack file to write")->required();
    CLI11_PARSE(app, argc, argv);
    if (*compile) return build(spec, out_path);

    jetrace::Track track;
    jetrace::TrackReport report;
    std::string error;
    double ms = 0;
    if (!load(spec, track, report, ms, error)) return fail(error);
    if (*inspect) {
        const json s = summary(track, report, ms);
        if (as_json) std::printf("%s\n", s.dump().c_str());
        else print_text(s);
        return 0;
    }
    std::ofstream out(svg_path, std::ios::binary | std::ios::trunc);
    out << jetrace::tools::render_svg(track, report, width_px);
    out.close();
    if (!out) return fail("cannot write '" + svg_path + "'");
    std::printf("wrote %s (%zu gates, %zu spawns)\n", svg_path.c_str(), track.checkpoints.size(), track.spawns.size());
    return 0;
}
