// jetrace-sim: an offline race of AI cars (optionally recorded as a
// replay), or one of the replay checks (sim_replay.hpp).
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/auth/key_file.hpp"
#include "jetrace/cli/finite.hpp"
#include "jetrace/core/race.hpp"
#include "jetrace/replay/writer.hpp"
#include "jetrace/tracks/track_io.hpp"
#include "replay_svg.hpp"
#include "sim_replay.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>

namespace {

struct RaceArgs {
    std::string track = "stadium";
    int cars = 8;
    double seconds = 60;
    std::uint64_t seed = 1;
    int laps = 3;
    std::string record;
    std::string sign_key;
};

void print_standings(const jetrace::Scene& scene, const jetrace::WorldState& state) {
    std::printf("%-4s %-5s %-8s %-5s %-6s %-8s %s\n", "pos", "car", "status", "lap", "gate", "respawns", "time_s");
    int pos = 1;
    unsigned long long respawns = 0;
    for (const auto& s : jetrace::standings(scene.track, state.cars, state.start_tick, scene.physics.tick_rate_hz)) {
        const std::uint32_t r = state.cars[static_cast<std::size_t>(s.slot)].respawns;
        respawns += r;
        if (s.finished) {
            std::printf("%-4d %-5d %-8s %-5d %-6s %-8u %.3f\n", pos, s.slot, "finished", s.lap, "-", r, s.finish_time_s);
        } else {
            std::printf("%-4d %-5d %-8s %-5d %-6d %-8u -\n", pos, s.slot, "racing", s.lap, s.next_checkpoint, r);
        }
        ++pos;
    }
    std::printf("respawns=%llu\n", respawns);
}

bool open_recording(const RaceArgs& a, const jetrace::Scene& scene, const jetrace::WorldState& start,
                    jetrace::replay::Writer& w) {
    std::optional<jetrace::replay::SigningKey> key;
    std::string error;
    if (!a.sign_key.empty()) {
        jetrace::auth::LoadedKey k;
        if (!jetrace::auth::load_key_file(a.sign_key, k, error) || !k.has_secret) {
            std::fprintf(stderr, "jetrace-sim: --sign-key: %s\n", error.empty() ? "not a secret key file" : error.c_str());
            return false;
        }
        key = k.secret;
    }
    if (w.open(a.record, jetrace::replay::header_for(scene, start), key)) return true;
    std::fprintf(stderr, "jetrace-sim: %s\n", w.error().c_str());
    return false;
}

bool finish_recording(const jetrace::Scene& scene, const jetrace::WorldState& st, jetrace::replay::Writer& w) {
    bool all = true;
    for (const auto& c : st.cars) all = all && (!c.active || c.finished);
    using jetrace::replay::EndReason;
    if (w.finish(jetrace::replay::trailer_for(scene, st, all ? EndReason::finished : EndReason::time_limit))) return true;
    std::fprintf(stderr, "jetrace-sim: %s\n", w.error().c_str());
    return false;
}

int run_race(const RaceArgs& a) {
    jetrace::Track track;
    std::string error;
    if (!jetrace::load_track(a.track, track, error)) {
        std::fprintf(stderr, "jetrace-sim: %s\n", error.c_str());
        return 2;
    }
    const jetrace::PhysicsSettings physics;
    const jetrace::Scene scene = jetrace::Scene::make(std::move(track), physics);
    jetrace::WorldState state = jetrace::start_race(scene, a.cars, a.laps);
    jetrace::replay::Writer writer;
    jetrace::replay::Recorder recorder(writer);
    if (!a.record.empty() && !open_recording(a, scene, state, writer)) return 2;
    const auto skills = jetrace::skills_for(a.cars, a.seed);
    const jetrace::Course course(scene);
    jetrace::StepScratch scratch;
    const auto ticks = static_cast<std::uint32_t>(a.seconds * physics.tick_rate_hz + 0.5);

    const auto t0 = std::chrono::steady_clock::now();
    jetrace::run_ai(course, state, skills, ticks, false, scratch, a.record.empty() ? nullptr : &recorder);
    const auto t1 = std::chrono::steady_clock::now();
    const double wall_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();

    std::printf("track %s: %zu triangles, %zu gates; %d cars, %d laps, %u ticks (%.1f s)\n", scene.track.name.c_str(),
                scene.track.triangles.size(), scene.track.checkpoints.size(), a.cars, a.laps, ticks, a.seconds);
    print_standings(scene, state);
    std::printf("wall_ms=%.1f car_steps=%llu\n", wall_ms,
                static_cast<unsigned long long>(ticks) * static_cast<unsigned long long>(a.cars));
    std::printf("state_hash=%s\n", jetrace::hash_hex(jetrace::state_hash(state)).c_str());
    if (!a.record.empty() && !finish_recording(scene, state, writer)) return 1;
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-sim: an offline race of AI cars on the deterministic core, and replay checks"};
    RaceArgs race;
    jetrace::sim::ReplayArgs rargs;
    std::string replay_path, verify_path, synctest_path, expect;
    std::vector<std::string> diff;
    bool rebuild = false;
    app.add_option("--track", race.track, "built-in track name (stadium, ring), a Wavefront .obj file or a track manifest (.json, docs/TRACKS.md)");
    app.add_option("--cars", race.cars, "number of AI cars")->check(CLI::Range(1, 64));
    app.add_option("--seconds", race.seconds, "simulated seconds")->check(jetrace::cli::finite() & CLI::Range(0.0, 86400.0));
    app.add_option("--seed", race.seed, "seed for the AI drivers' skills");
    app.add_option("--laps", race.laps, "laps to finish")->check(CLI::Range(1, 1000));
    app.add_option("--record", race.record, "write the offline race as a replay file");
    app.add_option("--sign-key", race.sign_key, "sign the --record replay with this secret key file")->needs("--record");
    auto* modes = app.add_option_group("replay checks", "exit 0: the check holds; 1: it does not; 2: bad input");
    modes->add_option("--replay", replay_path, "re-simulate a replay and print its state_hash=");
    modes->add_option("--verify", verify_path, "check every record, checkpoint, the trailer and the signature (JSON)");
    modes->add_option("--diff", diff, "A B: where two replays of one race first differ; A --rebuild: A against this build")
        ->expected(1, 2);
    modes->add_option("--synctest", synctest_path, "step every tick twice (fresh scratch, and rollbacks) and compare");
    modes->require_option(0, 1);
    std::optional<std::uint32_t> stop_tick;
    app.add_option("--stop-tick", stop_tick, "with --replay: print the world at this tick as JSON (car positions) instead")
        ->needs("--replay");
    std::string svg_path;
    int svg_width = 1200;
    app.add_option("--svg", svg_path, "with --replay: write a top-down SVG of the track with each car's line coloured by speed")
        ->needs("--replay")->excludes("--stop-tick");
    app.add_option("--svg-width", svg_width, "the --svg picture's width in pixels (200..8000)")->check(CLI::Range(200, 8000));
    app.add_flag("--rebuild", rebuild, "with --diff A: compare A against this build's re-simulation");
    app.add_option("--key", rargs.key_file, "the replay must be signed by this public key (FILE.pub)");
    app.add_option("--expect", expect, "the final state hash must be this (16 hex digits)");
    app.add_option("--rollback", rargs.rollback_ticks, "ticks each --synctest rollback re-simulates")->check(CLI::Range(1, 240));
    CLI11_PARSE(app, argc, argv);
    if (!expect.empty() && !(rargs.expect = jetrace::sim::parse_hash(expect))) {
        std::fprintf(stderr, "jetrace-sim: --expect: '%s' is not 16 hex digits\n", expect.c_str());
        return 2;
    }
    if ((diff.size() == 1) != rebuild) {
        std::fprintf(stderr, "jetrace-sim: --diff takes two replays, or one with --rebuild\n");
        return 2;
    }
    if (app.count("--track") > 0) rargs.track = race.track;
    if (!svg_path.empty()) return jetrace::sim::svg_file(replay_path, rargs, svg_path, svg_width);
    if (stop_tick) return jetrace::sim::state_at_file(replay_path, rargs, *stop_tick);
    if (!replay_path.empty()) return jetrace::sim::replay_file(replay_path, rargs);
    if (!verify_path.empty()) return jetrace::sim::verify_file(verify_path, rargs);
    if (!diff.empty()) return jetrace::sim::diff_files(diff[0], diff.size() > 1 ? diff[1] : "", rargs);
    if (!synctest_path.empty()) return jetrace::sim::synctest_file(synctest_path, rargs);
    return run_race(race);
}
