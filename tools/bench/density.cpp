// jetrace-bench density: one landscape (bench/landscape.hpp) meshed at
// several densities; 8 AI cars lap it. As in the study's track-size
// figure, the AI's inputs are recorded in an untimed run and the timed run
// steps the same race from the same start (thread CPU time of step() only).
#include "bench/common.hpp"
#include "bench/landscape.hpp"
#include "bench/track_load.hpp"
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <nlohmann/json.hpp>

#include <stdexcept>

namespace jetrace::bench {
namespace {

constexpr int kCars = 8;

struct Recorded {
    std::vector<Input> inputs;  // kCars per tick
    double candidates_per_car_step = 0;
    double ai_ns_per_car_step = 0;  // drive() alone, thread CPU time, one run
};

Recorded record(const Scene& sc, const WorldState& start, int ticks) {
    Recorded r;
    r.inputs.resize(static_cast<std::size_t>(kCars) * static_cast<std::size_t>(ticks));
    const std::vector<DriverSkill> skills = skills_for(kCars, 1);
    WorldState state = start;
    StepScratch scratch;
    const Course course(sc);
    double gathered = 0;
    double ai_ns = 0;
    for (int t = 0; t < ticks; ++t) {
        Input* in = &r.inputs[static_cast<std::size_t>(kCars) * static_cast<std::size_t>(t)];
        const CpuTimer ai;
        for (int i = 0; i < kCars; ++i) in[i] = drive(course, state, i, skills[static_cast<std::size_t>(i)]);
        ai_ns += ai.ns();
        step(sc, state, std::span<const Input>(in, kCars), scratch);
        for (const CarScratch& c : scratch.cars) gathered += static_cast<double>(c.candidates.triangles.size());
    }
    r.candidates_per_car_step = gathered / (static_cast<double>(ticks) * kCars);
    r.ai_ns_per_car_step = ai_ns / (static_cast<double>(ticks) * kCars);
    return r;
}

double timed_ns_per_car_step(const Scene& sc, const WorldState& start, const Recorded& r, int ticks,
                             std::uint64_t& end_hash) {
    WorldState state = start;
    StepScratch scratch;
    const CpuTimer timer;
    for (int t = 0; t < ticks; ++t) {
        step(sc, state, std::span<const Input>(&r.inputs[static_cast<std::size_t>(kCars) * static_cast<std::size_t>(t)], kCars),
             scratch);
    }
    const double ns = timer.ns() / (static_cast<double>(ticks) * kCars);
    end_hash = state_hash(state);
    return ns;
}

// The meshes measured: the landscape at each density, then each --track.
std::vector<Track> meshes(const DensityOptions& o) {
    std::vector<Track> out;
    for (int n : o.squares) out.push_back(landscape(n));
    for (const std::string& spec : o.tracks) {
        Track t;
        std::string error;
        if (!load_track(spec, t, error)) throw std::runtime_error(spec + ": " + error);
        out.push_back(std::move(t));
    }
    return out;
}

}  // namespace

int run_density(const DensityOptions& o) {
    const PhysicsSettings ps;
    const int ticks = static_cast<int>(o.seconds * ps.tick_rate_hz);
    const std::size_t cells = o.cell_sizes_m.size();
    std::vector<double> base(cells, 0.0);
    std::vector<Track> all;
    try {
        all = meshes(o);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "jetrace-bench: %s\n", e.what());
        return 1;
    }
    for (std::size_t m = 0; m < all.size(); ++m) {
        Track& track = all[m];
        const bool landscape_mesh = m < o.squares.size();
        // One scene per cell edge; the step's results do not depend on it.
        std::vector<Scene> scenes;
        for (std::size_t c = 0; c < cells; ++c) scenes.push_back(Scene::make(track, ps, o.cell_sizes_m[c]));
        Track().triangles.swap(track.triangles);
        const WorldState start = start_race(scenes[0], kCars, 1);
        const Recorded r = record(scenes[0], start, ticks);
        // Rounds: every cell edge once per round, side by side, each round
        // starting from the next edge (the first race of a round runs slower).
        std::vector<std::vector<double>> ns(cells);
        std::vector<std::uint64_t> hashes(cells, 0);
        for (int k = 0; k < o.repeats; ++k) {
            for (std::size_t i = 0; i < cells; ++i) {
                const std::size_t c = (i + static_cast<std::size_t>(k)) % cells;
                ns[c].push_back(timed_ns_per_car_step(scenes[c], start, r, ticks, hashes[c]));
            }
        }
        for (std::size_t c = 0; c < cells; ++c) {
            const Scene& sc = scenes[c];
            const double med = median(ns[c]);
            if (base[c] == 0) base[c] = med;
            nlohmann::json j;
            j["benchmark"] = "density";
            j["track"] = sc.track.name;
            j["triangles"] = sc.track.triangles.size();
            if (landscape_mesh) j["triangle_edge_m"] = kLandscapeSide_m / o.squares[m];
            j["cars"] = kCars;
            j["ticks"] = ticks;
            j["grid_cell_m"] = sc.grid.cell_size_m();
            j["grid_bytes_per_triangle"] = static_cast<double>(sc.grid.memory_bytes()) / static_cast<double>(sc.track.triangles.size());
            j["ns_per_car_step"] = med;
            j["relative_to_first"] = med / base[c];
            if (c > 0) {
                j["relative_to_first_cell"] = median_ratio(ns[c], ns[0]);
                j["same_result"] = hashes[c] == hashes[0];
            }
            j["candidates_per_car_step"] = r.candidates_per_car_step;
            j["ai_ns_per_car_step"] = r.ai_ns_per_car_step;
            std::printf("%s\n", j.dump().c_str());
            std::fflush(stdout);
        }
    }
    return 0;
}

}  // namespace jetrace::bench
