// jetrace-bench: benchmarks that print machine-readable JSON.
//   seed         the seed article's benchmark: one car idling on `stadium`,
//                grid on, then off (brute force); parked (the step as a
//                server runs it: a car at rest skips its push-out) and
//                with the push-out every frame (what the seed measured).
//   integrators  integrator error against analytic and fine-step references.
//   study        the speed-against-accuracy study: CSV files (tools/bench/study*.cpp).
//   bullet       side by side with Bullet (tools/bench/bullet.cpp; only when
//                built with Bullet).
//   landscape    writes the benchmark landscape (bench/landscape.hpp) as an
//                OBJ track (docs/TRACKS.md), for tools/view_bench.sh.
//   server       the server's tick and wire bytes per client, AI bots over an
//                in-memory network (tools/bench/server_tick.cpp).
#include "bench/common.hpp"
#include "bench/landscape.hpp"
#include "bench/replay_cost.hpp"
#include "bench/server_tick.hpp"
#include "bench/study.hpp"
#include "bench/track_load.hpp"
#include "jetrace/cli/finite.hpp"
#include "jetrace/core/world.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/track_io.hpp"
#ifdef JETRACE_HAVE_BULLET
#include "bench/bullet.hpp"
#endif

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace {

using jetrace::bench::Clock;
using jetrace::bench::fly;
using jetrace::bench::median;

// Nanoseconds per frame of one car idling for `frames` frames. `pushout`:
// the step forgets, before every frame, that the car is where it last
// found it clear of the track (and its contacts there), so every frame
// tests the car against the triangles as the seed's loop did; a car at
// rest otherwise skips that test (a parked car). The scratch is a cache:
// either way the car ends in the same state.
double idle_ns_per_frame(const jetrace::Scene& scene, std::uint32_t frames, bool pushout, std::uint64_t& hash_out) {
    jetrace::WorldState st = jetrace::make_world(1, 1);
    jetrace::spawn_car(scene, st, 0, 0);
    jetrace::StepScratch scratch;
    const jetrace::Input idle{};
    const auto t0 = Clock::now();
    if (pushout) {
        jetrace::step(scene, st, {&idle, 1}, scratch);
        for (std::uint32_t f = 1; f < frames; ++f) {
            scratch.cars[0].clear_valid = false;
            scratch.cars[0].contacts_valid = false;
            scratch.cars[0].rest_valid = false;
            jetrace::step(scene, st, {&idle, 1}, scratch);
        }
    } else {
        for (std::uint32_t f = 0; f < frames; ++f) jetrace::step(scene, st, {&idle, 1}, scratch);
    }
    const auto t1 = Clock::now();
    hash_out = jetrace::state_hash(st);
    return std::chrono::duration<double, std::nano>(t1 - t0).count() / frames;
}

// One variant's runs (ns per frame) and the final state of each.
struct SeedRuns {
    std::vector<double> ns;
    std::vector<std::uint64_t> hashes;
};

int run_seed(std::uint32_t frames, int repeats, bool grid_off) {
    jetrace::Track track = jetrace::make_oval(jetrace::stadium_params());
    const std::size_t triangles = track.triangles.size();
    const jetrace::PhysicsSettings physics;

    std::vector<double> build_ms;
    SeedRuns parked_on, parked_off, pushout_on, pushout_off;
    const auto run = [&](const jetrace::Scene& scene, bool pushout, SeedRuns& out) {
        std::uint64_t h = 0;
        out.ns.push_back(idle_ns_per_frame(scene, frames, pushout, h));
        out.hashes.push_back(h);
    };
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = Clock::now();
        jetrace::Scene scene = jetrace::Scene::make(track, physics);
        build_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
        scene.broadphase = jetrace::Broadphase::grid;
        run(scene, false, parked_on);
        run(scene, true, pushout_on);
        if (grid_off) {
            scene.broadphase = jetrace::Broadphase::brute_force;
            run(scene, false, parked_off);
            run(scene, true, pushout_off);
        }
    }
    // Every run of every variant ends in the same state: the grid finds what
    // brute force finds, and skipping a parked car's push-out changes nothing.
    bool same = true;
    for (const SeedRuns* v : {&parked_on, &parked_off, &pushout_on, &pushout_off}) {
        for (std::uint64_t h : v->hashes) same = same && h == parked_on.hashes.front();
    }
    jetrace::Scene scene = jetrace::Scene::make(track, physics);
    nlohmann::json j;
    j["benchmark"] = "seed";
    j["track"] = "stadium";
    j["triangles"] = triangles;
    j["frames"] = frames;
    j["repeats"] = repeats;
    j["parked_grid_on_ns_per_frame"] = median(parked_on.ns);
    j["pushout_grid_on_ns_per_frame"] = median(pushout_on.ns);
    j["parked_grid_on_runs_ns"] = parked_on.ns;
    j["pushout_grid_on_runs_ns"] = pushout_on.ns;
    if (grid_off) {
        j["parked_grid_off_ns_per_frame"] = median(parked_off.ns);
        j["pushout_grid_off_ns_per_frame"] = median(pushout_off.ns);
        j["parked_grid_off_runs_ns"] = parked_off.ns;
        j["pushout_grid_off_runs_ns"] = pushout_off.ns;
        j["pushout_speedup_grid"] = median(pushout_off.ns) / median(pushout_on.ns);
    }
    j["grid_build_ms"] = median(build_ms);
    j["grid_cell_m"] = scene.grid.cell_size_m();
    j["grid_cells"] = scene.grid.cell_count();  // occupied cells (the grid is sparse)
    j["grid_entries"] = scene.grid.entry_count();
    j["grid_bytes"] = scene.grid.memory_bytes();
    // The seed (Lua): 187,000 ns/frame grid on (incl. set-up), 1,630,000 off,
    // its push-out run every frame.
    j["seed_grid_on_ns_per_frame"] = 187000;
    j["seed_grid_off_ns_per_frame"] = 1630000;
    j["times_faster_than_seed_grid_on"] = 187000.0 / median(pushout_on.ns);
    j["same_final_state"] = same;
    std::printf("%s\n", j.dump().c_str());
    if (!same) std::fprintf(stderr, "jetrace-bench seed: the variants ended in different states\n");
    return same ? 0 : 1;
}

// Integrators against references: a ballistic jump without drag (analytic)
// and a flight with drag (reference: semi-implicit Euler at 7,680 Hz).
int run_integrators() {
    const double seconds = 4.0;
    jetrace::PhysicsSettings ref_ps;
    ref_ps.tick_rate_hz = 7680;
    const jetrace::Vec3 drag_ref = fly(ref_ps, seconds);
    const jetrace::Vec3& p0 = jetrace::bench::kFlightStart;
    const jetrace::Vec3& v0 = jetrace::bench::kFlightVelocity;
    const jetrace::Vec3 ballistic_ref = p0 + v0 * seconds + jetrace::Vec3(0, -0.5 * 9.81 * seconds * seconds, 0);
    for (jetrace::Integrator in : {jetrace::Integrator::explicit_euler, jetrace::Integrator::semi_implicit_euler,
                                   jetrace::Integrator::velocity_verlet}) {
        for (int hz : {30, 60, 120, 240, 480}) {
            jetrace::PhysicsSettings ps;
            ps.integrator = in;
            ps.tick_rate_hz = hz;
            const double drag_err = (fly(ps, seconds) - drag_ref).norm();
            ps.drag_per_m = 0.0;
            const double ballistic_err = (fly(ps, seconds) - ballistic_ref).norm();
            nlohmann::json j;
            j["benchmark"] = "integrators";
            j["integrator"] = jetrace::to_string(in);
            j["tick_rate_hz"] = hz;
            j["flight_s"] = seconds;
            j["ballistic_error_m"] = ballistic_err;
            j["drag_flight_error_m"] = drag_err;
            std::printf("%s\n", j.dump().c_str());
        }
    }
    return 0;
}

struct LandscapeOptions {
    int squares = 500;  // squares per side (2 n^2 triangles)
    int spawns = 8;     // starting-grid slots
    std::string out;    // the OBJ file
};

CLI::App* add_landscape(CLI::App& app, LandscapeOptions& o) {
    auto* sub = app.add_subcommand("landscape", "write the benchmark landscape as an OBJ track (2 n^2 triangles)");
    sub->add_option("--squares", o.squares, "squares per side (2 n^2 triangles; 16 or more keep the spawns above the mesh)")
        ->check(CLI::Range(2, 1414));
    sub->add_option("--spawns", o.spawns, "starting-grid slots, two columns behind gate 0")->check(CLI::Range(1, 64));
    sub->add_option("--out", o.out, "the OBJ file to write")->required();
    return sub;
}

// The landscape written as an OBJ track (docs/TRACKS.md) to `o.out`.
int run_landscape(const LandscapeOptions& o) {
    const std::string& out = o.out;
    const jetrace::Track track = jetrace::bench::landscape(o.squares, o.spawns);
    std::ofstream file(out, std::ios::binary | std::ios::trunc);
    file << jetrace::export_obj(track);
    file.close();
    if (!file) {
        std::fprintf(stderr, "jetrace-bench: cannot write %s\n", out.c_str());
        return 1;
    }
    nlohmann::json j;
    j["benchmark"] = "landscape";
    j["track"] = track.name;
    j["triangles"] = track.triangles.size();
    j["gates"] = track.checkpoints.size();
    j["spawns"] = track.spawns.size();
    j["file"] = out;
    std::printf("%s\n", j.dump().c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-bench: benchmarks printing one JSON object per result"};
    app.require_subcommand(1);
    std::uint32_t frames = 100000;
    int repeats = 3;
    auto* seed = app.add_subcommand("seed", "the seed's benchmark: one car idling on stadium, grid on then off");
    seed->add_option("--frames", frames, "physics frames per run")->check(CLI::Range(1u, 100000000u));
    seed->add_option("--repeats", repeats, "runs per variant; the median is reported")->check(CLI::Range(1, 100));
    bool no_grid_off = false;
    seed->add_flag("--no-grid-off", no_grid_off, "skip the brute-force runs (for profiling the grid path)");
    auto* integrators = app.add_subcommand("integrators", "integrator error against analytic and fine-step references");
    jetrace::bench::StudyOptions study_opts;
    auto* study = app.add_subcommand("study", "speed against accuracy: writes CSV files for tools/charts.sh");
    study->add_option("--out", study_opts.out_dir, "directory for the CSV files (created if missing)");
    study->add_flag("--quick", study_opts.quick, "fewer variants and shorter runs (under a minute)");
    study->add_option("--repeats", study_opts.repeats, "runs per timed variant; the median is reported")
        ->check(CLI::Range(1, 50));
    jetrace::bench::ReplayCostOptions replay_opts;
    auto* replay = app.add_subcommand("replay", "replay format costs: bytes per tick, recording overhead, verify time");
    replay->add_option("--cars", replay_opts.cars, "AI cars")->check(CLI::Range(1, 64));
    replay->add_option("--seconds", replay_opts.seconds, "simulated race length (s)")
        ->check(jetrace::cli::finite() & CLI::Range(1.0, 3600.0));
    replay->add_option("--repeats", replay_opts.repeats, "rounds; medians are reported")->check(CLI::Range(1, 50));
    replay->add_option("--dir", replay_opts.dir, "directory for the replay files (default: the temporary directory)");
#ifdef JETRACE_HAVE_BULLET
    jetrace::bench::BulletOptions bullet_opts;
    auto* bullet = app.add_subcommand("bullet", "the same scenarios in Bullet and in jetrace, in one run: JSON lines");
    jetrace::bench::add_bullet_options(*bullet, bullet_opts);
#endif
    jetrace::bench::TrackLoadOptions load_opts;
    auto* track_load = app.add_subcommand("track-load", "OBJ against .jtrack load time, and bytes per loaded triangle");
    track_load->add_option("--squares", load_opts.squares, "landscape squares per side (2 n^2 triangles)")
        ->check(CLI::Range(2, 1414));
    track_load->add_option("--repeats", load_opts.repeats, ".jtrack loads; the median is reported")->check(CLI::Range(1, 50));
    track_load->add_option("--obj-repeats", load_opts.obj_repeats, "source (OBJ or --track) loads; the median is reported")
        ->check(CLI::Range(1, 50));
    track_load->add_option("--track", load_opts.track, "a track file to measure instead of the landscape (.obj, .json)");
    track_load->add_option("--dir", load_opts.dir, "directory for the two files (default: the temporary directory)");
    jetrace::bench::DensityOptions density_opts;
    auto* density = app.add_subcommand("density", "ns per car-step on one landscape meshed at several densities");
    density->add_option("--squares", density_opts.squares, "squares per side of each mesh (2 n^2 triangles)")
        ->check(CLI::Range(2, 1414));
    density->add_option("--seconds", density_opts.seconds, "simulated seconds per timed race")
        ->check(jetrace::cli::finite() & CLI::Range(0.1, 600.0));
    density->add_option("--repeats", density_opts.repeats, "timed races per density; the median is reported")
        ->check(CLI::Range(1, 50));
    density->add_option("--track", density_opts.tracks, "tracks timed after the landscapes (built-in name or file)");
    density->add_option("--cell-m", density_opts.cell_sizes_m,
                        "grid cell edges compared side by side in each round (m; 0 = the grid's rule)")
        ->check(jetrace::cli::finite() & CLI::Range(0.0, 1e4));
    LandscapeOptions landscape_opts;
    auto* landscape = add_landscape(app, landscape_opts);
    jetrace::bench::ServerTickOptions server_opts;
    auto* server_tick = jetrace::bench::add_server_tick(app, server_opts);
    CLI11_PARSE(app, argc, argv);
    if (server_tick->parsed()) return jetrace::bench::run_server_tick(server_opts);
    if (landscape->parsed()) return run_landscape(landscape_opts);
    if (track_load->parsed()) return jetrace::bench::run_track_load(load_opts);
    if (density->parsed()) return jetrace::bench::run_density(density_opts);
    if (seed->parsed()) return run_seed(frames, repeats, !no_grid_off);
    if (integrators->parsed()) return run_integrators();
    if (study->parsed()) return jetrace::bench::run_study(study_opts);
    if (replay->parsed()) return jetrace::bench::run_replay_cost(replay_opts);
#ifdef JETRACE_HAVE_BULLET
    if (bullet->parsed()) return jetrace::bench::run_bullet(bullet_opts);
#endif
    return 2;
}
