// jetrace-verify: checks that this platform's build of the core reproduces
// the pinned results, and prints one JSON line per check. It needs no
// compiled third-party library, so it builds for x86-64, aarch64 and
// WebAssembly alike (tools/cross.sh runs it on all three).
//   jetrace-verify --golden               the race of the golden determinism test
//   jetrace-verify FILE [--expect HASH] [--signer KEY]   a replay on a built-in track: every
//       record, checkpoint, the trailer and (where this build has libsodium)
//       the signature, as jetrace-sim --verify does; exit 0 only if all hold
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

#if defined(__wasm32__)
constexpr const char* kPlatform = "wasm32";
#elif defined(__aarch64__)
constexpr const char* kPlatform = "aarch64";
#elif defined(__x86_64__)
constexpr const char* kPlatform = "x86_64";
#else
constexpr const char* kPlatform = "unknown";
#endif

// The race of tests/core/test_determinism.cpp's GoldenStadiumRace (whose
// kGoldenStadiumHash tools/cross.sh compares the printed hash with): 8 AI
// cars, 60 simulated seconds on `stadium`, skills seed 1, 3 laps, default
// PhysicsSettings.
struct AiRace {
    std::string track = "stadium";
    int cars = 8;
    int laps = 3;
    int seconds = 60;
    std::uint64_t seed = 1;
};

struct RaceResult {
    std::uint64_t state_hash = 0;
    std::uint64_t car_steps = 0;
    double wall_ms = 0;
};

// x to one decimal (prints as such: the nearest double to k / 10).
double one_decimal(double x) { return std::round(x * 10) / 10; }

// Runs `race` with every car driven by the AI and times the stepping only
// (not the track's construction).
bool run_race(const AiRace& race, RaceResult& out) {
    jetrace::Track track;
    if (!jetrace::make_builtin_track(race.track, track)) {
        std::fprintf(stderr, "jetrace-verify: no built-in track %s\n", race.track.c_str());
        return false;
    }
    const jetrace::PhysicsSettings physics;
    const jetrace::Scene scene = jetrace::Scene::make(std::move(track), physics);
    jetrace::WorldState state = jetrace::start_race(scene, race.cars, race.laps);
    const auto skills = jetrace::skills_for(race.cars, race.seed);
    const jetrace::Course course(scene);
    jetrace::StepScratch scratch;
    const auto ticks = static_cast<std::uint32_t>(race.seconds * physics.tick_rate_hz);

    const auto t0 = std::chrono::steady_clock::now();
    jetrace::run_ai(course, state, skills, ticks, false, scratch);
    const auto t1 = std::chrono::steady_clock::now();

    out.state_hash = jetrace::state_hash(state);
    out.car_steps = static_cast<std::uint64_t>(ticks) * static_cast<std::uint64_t>(race.cars);
    out.wall_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    return true;
}

// --golden: prints the golden race's state hash and timing.
int run_golden() {
    RaceResult r;
    if (!run_race(AiRace{}, r)) return 2;
    nlohmann::ordered_json line;
    line["mode"] = "golden";
    line["state_hash"] = jetrace::hash_hex(r.state_hash);
    line["car_steps"] = r.car_steps;
    line["wall_ms"] = one_decimal(r.wall_ms);
    line["ns_per_car_step"] = one_decimal(r.wall_ms * 1e6 / static_cast<double>(r.car_steps));
    line["platform"] = kPlatform;
    std::printf("%s\n", line.dump().c_str());
    return 0;
}

// 64 hex digits into a public key; false if not that.
bool parse_key(const std::string& hex, jetrace::replay::VerifyKey& key) {
    if (hex.size() != 2 * key.size()) return false;
    for (std::size_t i = 0; i < key.size(); ++i) {
        char* end = nullptr;
        const std::string byte = hex.substr(2 * i, 2);
        key[i] = static_cast<std::uint8_t>(std::strtoul(byte.c_str(), &end, 16));
        if (*end != '\0' || byte.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) return false;
    }
    return true;
}

// FILE: verifies a replay (the verdict JSON of jetrace-sim --verify, with the platform).
int run_verify(const std::string& path, const std::string& expect, const std::string& signer) {
    namespace replay = jetrace::replay;
    replay::VerifyOptions options;
    if (!signer.empty()) {
        replay::VerifyKey key{};
        if (!parse_key(signer, key)) {
            std::fprintf(stderr, "jetrace-verify: --signer: '%s' is not 64 hex digits\n", signer.c_str());
            return 2;
        }
        options.trusted_key = key;
    }
    if (!expect.empty()) {
        char* end = nullptr;
        options.expect_hash = std::strtoull(expect.c_str(), &end, 16);
        if (expect.size() != 16 || *end != '\0') {
            std::fprintf(stderr, "jetrace-verify: --expect: '%s' is not 16 hex digits\n", expect.c_str());
            return 2;
        }
    }
    replay::FileSource src;
    std::string error;
    if (!src.open(path, error, replay::kMaxFileBytes)) {
        std::fprintf(stderr, "jetrace-verify: %s\n", error.c_str());
        return 2;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const replay::Verdict v = replay::verify(src, replay::scene_for(jetrace::load_builtin), options);
    const auto t1 = std::chrono::steady_clock::now();
    nlohmann::ordered_json line;
    line["mode"] = "verify";
    line["platform"] = kPlatform;
    line["wall_ms"] = one_decimal(std::chrono::duration<double, std::milli>(t1 - t0).count());
    line["verdict"] = nlohmann::json::parse(replay::to_json(v));
    std::printf("%s\n", line.dump().c_str());
    return v.ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-verify: checks that this platform's core reproduces the pinned results (one JSON line each)"};
    bool golden = false;
    std::string replay_path, expect, signer;
    app.add_flag("--golden", golden, "run the golden determinism race and print its state hash and timing");
    app.add_option("replay", replay_path, "a replay file to verify (built-in tracks only)")->excludes("--golden");
    app.add_option("--expect", expect, "with a replay: its final state hash must be this (16 hex digits)")
        ->needs("replay");
    app.add_option("--signer", signer,
                   "with a replay: it must be signed by this Ed25519 public key (64 hex digits, the verdict's \"signer\")")
        ->needs("replay");
    CLI11_PARSE(app, argc, argv);

    if (golden) return run_golden();
    if (!replay_path.empty()) return run_verify(replay_path, expect, signer);
    std::fprintf(stderr, "jetrace-verify: nothing to verify\n%s", app.help().c_str());
    return 2;
}
