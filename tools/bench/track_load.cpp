#include "bench/track_load.hpp"

#include "bench/common.hpp"
#include "bench/landscape.hpp"
#include "jetrace/ai/driver_ai.hpp"
#include "jetrace/tracks/jtrack.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <malloc.h>
#include <unistd.h>

namespace jetrace::bench {
namespace {

// Resident memory of this process (unit: bytes), after returning freed heap
// memory to the system.
double resident_bytes() {
    ::malloc_trim(0);
    std::ifstream statm("/proc/self/statm");
    double pages = 0, resident = 0;
    statm >> pages >> resident;
    return resident * 4096.0;
}

// The bytes a loaded track, its scene and the AI's road profile of it hold
// in their arrays.
double counted_bytes(const Scene& sc, const RoadProfile& road) {
    const Track& t = sc.track;
    return static_cast<double>(sizeof(Scene) + t.name.capacity() + t.triangles.capacity() * sizeof(Triangle) +
                               t.checkpoints.capacity() * sizeof(Checkpoint) + t.spawns.capacity() * sizeof(Pose) +
                               sc.grid.memory_bytes() + road.memory_bytes());
}

struct LoadTime {
    double wall_ms = 0;  // median wall time
    double cpu_ms = 0;   // median thread CPU time (what a shared machine's waiting leaves out)
};

// `repeats` load_track(path); the last track in `out`.
LoadTime time_loads(const std::string& path, int repeats, Track& out) {
    std::vector<double> wall, cpu;
    for (int r = 0; r < repeats; ++r) {
        Track t;
        std::string error;
        const auto t0 = Clock::now();
        const CpuTimer timer;
        if (!load_track(path, t, error)) throw std::runtime_error(error);
        cpu.push_back(timer.ns() / 1e6);
        wall.push_back(ns_since(t0) / 1e6);
        out = std::move(t);
    }
    return {median(wall), median(cpu)};
}

bool write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    return static_cast<bool>(out);
}

}  // namespace

int run_track_load(const TrackLoadOptions& o) {
    const std::filesystem::path dir = o.dir.empty() ? std::filesystem::temp_directory_path() : std::filesystem::path(o.dir);
    const std::string stem = "jetrace-landscape-" + std::to_string(o.squares) + "-" + std::to_string(::getpid());
    const std::string obj = (dir / (stem + ".obj")).string(), jtrack = (dir / (stem + ".jtrack")).string();
    const bool own_source = o.track.empty();
    const std::string source = own_source ? obj : o.track;
    if (own_source && !write_text(obj, export_obj(landscape(o.squares)))) {
        std::fprintf(stderr, "jetrace-bench: cannot write %s\n", obj.c_str());
        return 1;
    }
    // As a user does: the OBJ loaded, then compiled (same identity).
    std::uint64_t identity = 0;
    LoadTime obj_time;
    {
        Track parsed;
        obj_time = time_loads(source, o.obj_repeats, parsed);
        identity = parsed.identity();
        std::string error;
        if (!write_jtrack_file(parsed, jtrack, error)) {
            std::fprintf(stderr, "jetrace-bench: %s\n", error.c_str());
            return 1;
        }
    }
    const double rss0 = resident_bytes();
    Track compiled;
    const LoadTime jtrack_time = time_loads(jtrack, o.repeats, compiled);
    const auto g0 = Clock::now();
    const Scene scene = Scene::make(std::move(compiled), PhysicsSettings{});
    const double grid_ms = ns_since(g0) / 1e6;
    const auto r0 = Clock::now();
    const Course course(scene);
    const double road_ms = ns_since(r0) / 1e6;
    const double rss1 = resident_bytes();
    const double n = static_cast<double>(scene.track.triangles.size());
    nlohmann::json j;
    j["benchmark"] = "track-load";
    j["track"] = scene.track.name;
    j["triangles"] = scene.track.triangles.size();
    j["source"] = own_source ? "landscape OBJ" : o.track;
    std::error_code ec;  // a built-in name has no file
    const auto source_bytes = std::filesystem::file_size(source, ec);
    j["source_bytes"] = ec ? 0 : source_bytes;
    j["jtrack_bytes"] = std::filesystem::file_size(jtrack);
    j["source_load_ms"] = obj_time.wall_ms;
    j["source_load_cpu_ms"] = obj_time.cpu_ms;
    j["jtrack_load_ms"] = jtrack_time.wall_ms;
    j["jtrack_load_cpu_ms"] = jtrack_time.cpu_ms;
    j["speedup"] = obj_time.wall_ms / jtrack_time.wall_ms;
    j["speedup_cpu"] = obj_time.cpu_ms / jtrack_time.cpu_ms;
    j["grid_build_ms"] = grid_ms;
    j["road_profile_build_ms"] = road_ms;
    j["grid_cell_m"] = scene.grid.cell_size_m();
    j["identity_equal"] = scene.track.identity() == identity;
    j["triangle_struct_bytes"] = sizeof(Triangle);
    j["track_bytes_per_triangle"] = static_cast<double>(scene.track.triangles.capacity() * sizeof(Triangle)) / n;
    j["grid_bytes_per_triangle"] = static_cast<double>(scene.grid.memory_bytes()) / n;
    j["road_profile_bytes"] = course.road().memory_bytes();
    j["grid_entries_per_triangle"] = static_cast<double>(scene.grid.entry_count()) / n;
    j["counted_bytes_per_triangle"] = counted_bytes(scene, course.road()) / n;
    j["resident_bytes_per_triangle"] = (rss1 - rss0) / n;
    std::printf("%s\n", j.dump().c_str());
    if (own_source) std::filesystem::remove(obj);
    std::filesystem::remove(jtrack);
    return 0;
}

}  // namespace jetrace::bench
