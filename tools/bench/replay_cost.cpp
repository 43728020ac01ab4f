#include "bench/replay_cost.hpp"

#include "bench/common.hpp"
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/auth/connect_token.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/replay/writer.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>

namespace jetrace::bench {

namespace {

/// Every tick's inputs of the AI race, recorded once.
struct Race {
    WorldState start;
    std::vector<std::vector<Input>> inputs;
};

class InputTape final : public StepObserver {
public:
    explicit InputTape(Race& r) : race_(&r) {}
    void before_step(const WorldState&, std::span<const Input> in) override { race_->inputs.emplace_back(in.begin(), in.end()); }
    void after_step(const WorldState&) override {}

private:
    Race* race_;
};

/// Steps the race (and records it when `path` is set); returns the wall ns.
double run(const Scene& scene, const Race& race, const std::string& path, const std::optional<replay::SigningKey>& key,
           std::uint64_t* bytes = nullptr) {
    WorldState st = race.start;
    StepScratch scratch;
    replay::Writer w;
    const auto t0 = Clock::now();
    if (!path.empty() && !w.open(path, replay::header_for(scene, st), key)) return -1;
    for (const auto& in : race.inputs) {
        if (w.is_open()) w.record_tick(st.tick, {}, in);
        step(scene, st, in, scratch);
        if (w.is_open()) w.stepped(st);
    }
    if (!path.empty()) {
        if (!w.finish(replay::trailer_for(scene, st, replay::EndReason::time_limit))) return -1;
    }
    const double ns = ns_since(t0);
    if (bytes) *bytes = w.bytes_written();
    return ns;
}

}  // namespace

namespace {

// The inputs of an AI race of o.cars for o.seconds.
Race ai_race(const Scene& scene, const ReplayCostOptions& o) {
    Race race;
    race.start = start_race(scene, o.cars, 3);
    {
        WorldState st = race.start;
        StepScratch scratch;
        InputTape tape(race);
        run_ai(Course(scene), st, skills_for(o.cars, 1), static_cast<std::uint32_t>(o.seconds * 120 + 0.5), false, scratch, &tape);
    }
    return race;
}

}  // namespace

int run_replay_cost(const ReplayCostOptions& o) {
    Track track;
    make_builtin_track("stadium", track);
    const Scene scene = Scene::make(std::move(track), PhysicsSettings{});
    const Race race = ai_race(scene, o);
    const std::string dir = o.dir.empty() ? std::filesystem::temp_directory_path().string() : o.dir;
    const std::string plain = dir + "/jetrace-bench-replay.jtr", signed_path = dir + "/jetrace-bench-replay-signed.jtr";
    const std::optional<replay::SigningKey> key = auth::generate_key_pair().secret_key;
    std::vector<double> off, on, sig, ratio, sig_ratio, verify_ms;
    std::uint64_t bytes = 0, signed_bytes = 0;
    for (int r = 0; r < o.repeats; ++r) {
        off.push_back(run(scene, race, "", std::nullopt));
        on.push_back(run(scene, race, plain, std::nullopt, &bytes));
        sig.push_back(run(scene, race, signed_path, key, &signed_bytes));
        if (on.back() < 0 || sig.back() < 0) {
            std::fprintf(stderr, "jetrace-bench replay: cannot write replays in %s\n", dir.c_str());
            return 1;
        }
        ratio.push_back(on.back() / off.back() - 1);
        sig_ratio.push_back(sig.back() / off.back() - 1);
        replay::FileSource src;
        std::string error;
        src.open(signed_path, error, replay::kMaxFileBytes);
        const auto t0 = Clock::now();
        const replay::Verdict v = replay::verify(src, replay::scene_for(load_builtin));
        verify_ms.push_back(ns_since(t0) / 1e6);
        if (!v.ok) {
            std::fprintf(stderr, "jetrace-bench replay: the replay does not verify: %s\n", replay::to_json(v).c_str());
            return 1;
        }
    }
    std::filesystem::remove(plain);
    std::filesystem::remove(signed_path);
    const double ticks = static_cast<double>(race.inputs.size());
    // Version 1: "JTRREPL1", u16 version, u16 + name, u64 identity, u64
    // physics hash, u16 tick rate, the state; per tick u8 tag, u32 tick,
    // u8 removed count, u16 slot count, u16 per slot.
    const double v1_per_tick = 8.0 + 2.0 * o.cars;
    nlohmann::ordered_json j;
    j["cars"] = o.cars;
    j["ticks"] = race.inputs.size();
    j["bytes"] = bytes;
    j["bytes_per_tick"] = static_cast<double>(bytes) / ticks;
    j["v1_bytes_per_tick"] = v1_per_tick;
    j["signed_bytes"] = signed_bytes;
    j["step_ms_median"] = median(off) / 1e6;
    j["step_and_record_ms_median"] = median(on) / 1e6;
    j["record_overhead_pct_by_round"] = 100 * median(ratio);
    j["record_signed_overhead_pct_by_round"] = 100 * median(sig_ratio);
    j["verify_ms_median"] = median(verify_ms);
    j["repeats"] = o.repeats;
    std::printf("%s\n", j.dump().c_str());
    return 0;
}

}  // namespace jetrace::bench
