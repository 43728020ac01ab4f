// jetrace-sim: an offline race of AI cars, or the re-simulation of a replay.
#include "jetrace/offline_race.hpp"
#include "jetrace/race.hpp"
#include "jetrace/server/replay.hpp"
#include "jetrace/track_io.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>

namespace {

// Re-simulates a replay and prints the same state_hash= line as the server.
int run_replay_file(const std::string& path, std::string track_spec, bool track_given) {
    jetrace::Replay replay;
    std::string error;
    if (!jetrace::read_replay(path, replay, error)) {
        std::fprintf(stderr, "jetrace-sim: %s\n", error.c_str());
        return 2;
    }
    if (!track_given) track_spec = replay.header.track_name;
    jetrace::Track track;
    if (!jetrace::load_track(track_spec, track, error)) {
        std::fprintf(stderr, "jetrace-sim: %s (pass --track FILE.obj for an imported track)\n", error.c_str());
        return 2;
    }
    jetrace::PhysicsSettings physics;
    physics.tick_rate_hz = replay.header.tick_rate_hz;
    if (const std::string e = jetrace::validate(physics); !e.empty()) {
        std::fprintf(stderr, "jetrace-sim: replay: %s\n", e.c_str());
        return 2;
    }
    const jetrace::Scene scene = jetrace::Scene::make(std::move(track), physics);
    if (!jetrace::check_replay(scene, replay, jetrace::physics_fingerprint(physics), error)) {
        std::fprintf(stderr, "jetrace-sim: %s\n", error.c_str());
        return 2;
    }
    const jetrace::WorldState final_state = jetrace::run_replay(scene, replay);
    std::printf("replay %s: track %s, %zu ticks%s\n", path.c_str(), scene.track.name.c_str(), replay.ticks.size(),
                replay.truncated ? " (last record cut short, ignored)" : "");
    std::printf("state_hash=%s\n", jetrace::hash_hex(jetrace::state_hash(final_state)).c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-sim: an offline race of AI cars on the deterministic core"};
    std::string track_spec = "stadium";
    int cars = 8;
    double seconds = 60;
    std::uint64_t seed = 1;
    int laps = 3;
    app.add_option("--track", track_spec, "built-in track name (stadium, ring) or a Wavefront .obj file");
    app.add_option("--cars", cars, "number of AI cars")->check(CLI::Range(1, 64));
    app.add_option("--seconds", seconds, "simulated seconds")->check(CLI::Range(0.0, 86400.0));
    app.add_option("--seed", seed, "seed for the AI drivers' skills");
    app.add_option("--laps", laps, "laps to finish")->check(CLI::Range(1, 1000));
    std::string replay_path;
    app.add_option("--replay", replay_path, "re-simulate a replay recorded by jetrace-server --record")
        ->excludes("--cars")
        ->excludes("--seconds")
        ->excludes("--seed")
        ->excludes("--laps");
    CLI11_PARSE(app, argc, argv);
    if (!replay_path.empty()) return run_replay_file(replay_path, track_spec, app.count("--track") > 0);

    jetrace::Track track;
    std::string error;
    if (!jetrace::load_track(track_spec, track, error)) {
        std::fprintf(stderr, "jetrace-sim: %s\n", error.c_str());
        return 2;
    }
    const jetrace::PhysicsSettings physics;
    const jetrace::Scene scene = jetrace::Scene::make(std::move(track), physics);
    jetrace::WorldState state = jetrace::start_race(scene, cars, laps);
    const auto skills = jetrace::skills_for(cars, seed);
    jetrace::StepScratch scratch;
    const auto ticks = static_cast<std::uint32_t>(seconds * physics.tick_rate_hz + 0.5);

    const auto t0 = std::chrono::steady_clock::now();
    jetrace::run_ai(scene, state, skills, ticks, false, scratch);
    const auto t1 = std::chrono::steady_clock::now();
    const double wall_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();

    std::printf("track %s: %zu triangles, %zu gates; %d cars, %d laps, %u ticks (%.1f s)\n", scene.track.name.c_str(),
                scene.track.triangles.size(), scene.track.checkpoints.size(), cars, laps, ticks, seconds);
    std::printf("%-4s %-5s %-8s %-5s %-6s %s\n", "pos", "car", "status", "lap", "gate", "time_s");
    int pos = 1;
    for (const auto& s : jetrace::standings(scene.track, state.cars, state.start_tick, physics.tick_rate_hz)) {
        if (s.finished) {
            std::printf("%-4d %-5d %-8s %-5d %-6s %.3f\n", pos, s.slot, "finished", s.lap, "-", s.finish_time_s);
        } else {
            std::printf("%-4d %-5d %-8s %-5d %-6d -\n", pos, s.slot, "racing", s.lap, s.next_checkpoint);
        }
        ++pos;
    }
    std::printf("wall_ms=%.1f car_steps=%llu\n", wall_ms,
                static_cast<unsigned long long>(ticks) * static_cast<unsigned long long>(cars));
    std::printf("state_hash=%s\n", jetrace::hash_hex(jetrace::state_hash(state)).c_str());
    return 0;
}
