// How the cost scales (issue 4):
//   grid_cell.csv   stadium, 8 AI cars: ns per car-step, grid memory and
//                   build time for each grid cell edge ("cells": occupied
//                   cells, the only ones the sparse grid stores);
//   track_size.csv  1,384 to ~1,000,000 triangles, two ways: the stadium
//                   with a finer floor ("refined", and "refined_cell5" with
//                   5 m grid cells) and n x n stadiums side by side
//                   ("tiled"): ns per car-step of 8 AI cars, grid build;
//   cars.csv        1 to 1,000 AI cars on the stadium with car-car
//                   collisions: ns per tick, and the part spent in collide_cars.
// Only step() is timed (thread CPU time); the AI's inputs are computed
// outside the clock.
#include "bench/study.hpp"
#include "jetrace/ai/driver_ai.hpp"
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/core/race.hpp"
#include "lab/scenes.hpp"

#include <algorithm>
#include <chrono>

namespace jetrace::bench {
namespace {

struct Timing {
    double ns_per_tick = 0;
    double collide_ns_per_tick = 0;
};

// Steps `ticks` ticks of `state` with AI inputs. The inputs are recorded in
// a first, untimed run; the timed run replays them from the same state (the
// step is deterministic, so it follows the same trajectory) and times the
// whole loop in thread CPU time. collide_cars is timed per tick on a copy of
// the cars (thread CPU time too, less the clock's own cost, which on this
// virtual machine is about a microsecond: meaningful from tens of cars on).
Timing race(const Scene& sc, const WorldState& start, int ticks, bool time_collide) {
    const int n = static_cast<int>(start.cars.size());
    const auto un = static_cast<std::size_t>(n);
    const std::vector<DriverSkill> skills = skills_for(n, 1);
    std::vector<Input> inputs(un * static_cast<std::size_t>(ticks));
    StepScratch scratch;
    const Course course(sc);
    WorldState state = start;
    double collide_ns = 0;
    for (int t = 0; t < ticks; ++t) {
        Input* in = &inputs[un * static_cast<std::size_t>(t)];
        for (int i = 0; i < n; ++i) in[i] = drive(course, state, i, skills[static_cast<std::size_t>(i)]);
        step(sc, state, std::span<const Input>(in, un), scratch);
        if (time_collide) {
            std::vector<CarState> copy = state.cars;
            const CpuTimer timer;
            collide_cars(sc.physics.car_radius_m, copy);
            collide_ns += timer.ns() - cpu_timer_overhead_ns();
        }
    }
    state = start;
    StepScratch timed_scratch;
    const CpuTimer timer;
    for (int t = 0; t < ticks; ++t) {
        step(sc, state, std::span<const Input>(&inputs[un * static_cast<std::size_t>(t)], un), timed_scratch);
    }
    return {timer.ns() / ticks, collide_ns / ticks};
}

constexpr int kRaceCars = 8;

double ns_per_car_step(const Scene& sc, int ticks, int repeats) {
    std::vector<double> v;
    for (int r = 0; r < repeats; ++r) v.push_back(race(sc, start_race(sc, kRaceCars, 1), ticks, false).ns_per_tick / kRaceCars);
    return median(v);
}

// Cars on a 6 m lattice on the stadium's straights (1,542 places).
WorldState lattice(const Scene& sc, int n) {
    WorldState st = make_world(n, 1);
    const double rest = sc.physics.car_radius_m + sc.physics.resolver_epsilon_m;
    int k = 0;
    const auto put = [&](double x, double z, const Vec3& fwd) {
        if (k >= n) return;
        CarState& c = st.cars[static_cast<std::size_t>(k++)];
        c.active = true;
        place_car(c, Pose{Vec3(x, rest, z), fwd, Vec3(0, 1, 0)});
    };
    for (double x = -100; x < 240 && k < n; x += 6)
        for (double z = -15; z <= 15; z += 6) put(x, z, Vec3(1, 0, 0));
    for (double x = 1200; x > 0 && k < n; x -= 6)
        for (double z = 285; z <= 315; z += 6) put(x, z, Vec3(-1, 0, 0));
    return st;
}

// grid_cell.csv: one track, the grid's cell size varied.
void study_grid_cell(const StudyOptions& o, const PhysicsSettings& ps, const Track& stadium, int ticks) {
    Csv csv(o.out_dir, "grid_cell.csv",
            {"cell_m", "cells", "entries", "grid_bytes", "build_ms", "ns_per_car_step", "is_default"});
    const double def_cell = UniformGrid::cell_size_for(stadium.triangles, stadium.bounds, ps.car_radius_m);
    std::vector<double> cells = o.quick ? std::vector<double>{5, 10, 40, 160}
                                        : std::vector<double>{5, 7.5, 10, 15, 20, 30, 40, 80, 160, 400};
    if (std::find(cells.begin(), cells.end(), def_cell) == cells.end()) {
        cells.insert(std::lower_bound(cells.begin(), cells.end(), def_cell), def_cell);
    }
    std::vector<Scene> scenes;
    std::vector<double> build_ms;
    for (double cell : cells) {
        const CpuTimer timer;
        scenes.push_back(Scene::make(stadium, ps, cell));
        build_ms.push_back(timer.ns() * 1e-6);
    }
    // Timing rounds over every cell size; medians reported.
    std::vector<std::vector<double>> ns(scenes.size());
    for (int r = 0; r < o.repeats; ++r) {
        for (std::size_t k = 0; k < scenes.size(); ++k) ns[k].push_back(ns_per_car_step(scenes[k], ticks, 1));
    }
    for (std::size_t k = 0; k < scenes.size(); ++k) {
        const UniformGrid& g = scenes[k].grid;
        csv.cell(cells[k]).cell(static_cast<long long>(g.cell_count())).cell(g.entry_count());
        csv.cell(g.memory_bytes()).cell(build_ms[k]).cell(median(ns[k])).cell(cells[k] == def_cell).end();
    }
}

// track_size.csv: finer and larger tracks, the default cell size.
void study_track_size(const StudyOptions& o, const PhysicsSettings& ps, int ticks) {
    Csv csv(o.out_dir, "track_size.csv",
            {"kind", "parameter", "triangles", "cell_m", "grid_bytes", "build_ms", "ns_per_car_step"});
    const auto measure = [&](const char* kind, double param, const Track& track, double cell_m = 0.0) {
        const CpuTimer timer;
        const Scene sc = Scene::make(track, ps, cell_m);
        const double build = timer.ns() * 1e-6;
        csv.cell(kind).cell(param).cell(track.triangles.size()).cell(sc.grid.cell_size_m());
        csv.cell(sc.grid.memory_bytes()).cell(build).cell(ns_per_car_step(sc, ticks, o.repeats)).end();
    };
    const std::vector<double> floors = o.quick ? std::vector<double>{35, 5, 1.15}
                                               : std::vector<double>{35, 17.5, 10, 5, 2.5, 1.6, 1.15};
    for (double f : floors) {
        const Track t = lab::refined_stadium(f);
        measure("refined", f, t);
        // The same with 5 m cells (below the rule's 4 radii): fewer candidates, 8x the cells.
        if (f <= 5.0) measure("refined_cell5", f, t, 5.0);
    }
    const std::vector<int> tiles = o.quick ? std::vector<int>{1, 5, 27} : std::vector<int>{1, 2, 4, 8, 14, 20, 27};
    for (int n : tiles) measure("tiled", n, lab::tiled_stadium(n));
}

// cars.csv: the cost of a tick against the number of cars.
void study_car_count(const StudyOptions& o, const PhysicsSettings& ps, const Track& stadium) {
    Csv csv(o.out_dir, "cars.csv", {"cars", "ns_per_tick", "ns_per_car_step", "collide_ns_per_tick"});
    const Scene sc = Scene::make(stadium, ps);
    const std::vector<int> counts = o.quick ? std::vector<int>{1, 10, 100, 1000}
                                            : std::vector<int>{1, 2, 5, 10, 20, 50, 100, 200, 500, 1000};
    const int car_ticks = static_cast<int>((o.quick ? 0.5 : 2.0) * ps.tick_rate_hz);
    for (int n : counts) {
        std::vector<double> tick_ns, collide_ns;
        for (int r = 0; r < o.repeats; ++r) {
            const Timing t = race(sc, lattice(sc, n), car_ticks, true);
            tick_ns.push_back(t.ns_per_tick);
            collide_ns.push_back(t.collide_ns_per_tick);
        }
        csv.cell(n).cell(median(tick_ns)).cell(median(tick_ns) / n).cell(median(collide_ns)).end();
    }
}

}  // namespace

void study_scale(const StudyOptions& o) {
    const PhysicsSettings ps;
    const int ticks = static_cast<int>((o.quick ? 2.0 : 10.0) * ps.tick_rate_hz);
    const Track stadium = make_oval(stadium_params());
    study_grid_cell(o, ps, stadium, ticks);
    study_track_size(o, ps, ticks);
    study_car_count(o, ps, stadium);
}

}  // namespace jetrace::bench
