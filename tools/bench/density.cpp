// jetrace-bench density: one landscape (bench/landscape.hpp) meshed at
// several densities; 8 AI cars lap it. As in the study's track-size
// figure, the AI's inputs are recorded in an untimed run and the timed run
// steps the same race from the same start (thread CPU time of step() only).
#include "bench/common.hpp"
#include "bench/landscape.hpp"
#include "bench/track_load.hpp"
#include "jetrace/offline_race.hpp"

#include <nlohmann/json.hpp>

namespace jetrace::bench {
namespace {

constexpr int kCars = 8;

struct Recorded {
    std::vector<Input> inputs;  // kCars per tick
    double candidates_per_car_step = 0;
};

Recorded record(const Scene& sc, const WorldState& start, int ticks) {
    Recorded r;
    r.inputs.resize(static_cast<std::size_t>(kCars) * static_cast<std::size_t>(ticks));
    const std::vector<DriverSkill> skills = skills_for(kCars, 1);
    WorldState state = start;
    StepScratch scratch;
    double gathered = 0;
    for (int t = 0; t < ticks; ++t) {
        Input* in = &r.inputs[static_cast<std::size_t>(kCars) * static_cast<std::size_t>(t)];
        for (int i = 0; i < kCars; ++i) in[i] = drive(sc, state, i, skills[static_cast<std::size_t>(i)]);
        step(sc, state, std::span<const Input>(in, kCars), scratch);
        for (const CarScratch& c : scratch.cars) gathered += static_cast<double>(c.candidates.triangles.size());
    }
    r.candidates_per_car_step = gathered / (static_cast<double>(ticks) * kCars);
    return r;
}

double timed_ns_per_car_step(const Scene& sc, const WorldState& start, const Recorded& r, int ticks) {
    WorldState state = start;
    StepScratch scratch;
    const CpuTimer timer;
    for (int t = 0; t < ticks; ++t) {
        step(sc, state, std::span<const Input>(&r.inputs[static_cast<std::size_t>(kCars) * static_cast<std::size_t>(t)], kCars),
             scratch);
    }
    return timer.ns() / (static_cast<double>(ticks) * kCars);
}

}  // namespace

int run_density(const DensityOptions& o) {
    const PhysicsSettings ps;
    const int ticks = static_cast<int>(o.seconds * ps.tick_rate_hz);
    double base = 0;
    for (int n : o.squares) {
        const Scene sc = Scene::make(landscape(n), ps);
        const WorldState start = start_race(sc, kCars, 1);
        const Recorded r = record(sc, start, ticks);
        std::vector<double> ns;
        for (int k = 0; k < o.repeats; ++k) ns.push_back(timed_ns_per_car_step(sc, start, r, ticks));
        const double med = median(ns);
        if (base == 0) base = med;
        nlohmann::json j;
        j["benchmark"] = "density";
        j["track"] = sc.track.name;
        j["triangles"] = sc.track.triangles.size();
        j["triangle_edge_m"] = kLandscapeSide_m / n;
        j["cars"] = kCars;
        j["ticks"] = ticks;
        j["ns_per_car_step"] = med;
        j["relative_to_first"] = med / base;
        j["candidates_per_car_step"] = r.candidates_per_car_step;
        std::printf("%s\n", j.dump().c_str());
        std::fflush(stdout);
    }
    return 0;
}

}  // namespace jetrace::bench
