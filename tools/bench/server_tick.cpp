#include "bench/server_tick.hpp"

#include "bench/common.hpp"
#include "jetrace/ai/driver_ai.hpp"
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/ai/pilot.hpp"
#include "jetrace/cli/finite.hpp"
#include "jetrace/cli/logging.hpp"
#include "jetrace/client/race_client.hpp"
#include "jetrace/net/memory_transport.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/server/race_server.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace jetrace::bench {

namespace {

/// Bot k drives with skills_for(bots, kSkillSeed)[k], as LiveRace's bot k does.
constexpr std::uint64_t kSkillSeed = 11;
/// The virtual clock's step, as LiveRace's (unit: us).
constexpr std::uint64_t kStepUs = 1000;
/// The lobby and countdown must be over by then (unit: us of the virtual clock).
constexpr std::uint64_t kStartLimitUs = 60'000'000;

/// An AI driver on its own connection (the transport is declared first: it
/// outlives the client that uses it).
struct Bot {
    std::unique_ptr<net::Transport> net;
    std::unique_ptr<client::RaceClient> client;
    Pilot pilot;  // its AI: skill, course of the scene the client races on, held input
    client::InputSource input;
};

/// What one run measured.
struct Run {
    /// Thread CPU time of each server tick of the window (unit: us).
    std::vector<double> tick_us;
    /// The same split: ticks that sent snapshots, and the others (unit: us).
    std::vector<double> snapshot_tick_us;
    std::vector<double> plain_tick_us;
    /// Thread CPU time of every RaceServer::update of the window, ticking or
    /// not (unit: us).
    double update_us = 0;
    /// Ticks stepped in the window.
    std::uint64_t ticks = 0;
    /// Payload bytes the server end sent and received in the window (unit: bytes).
    std::uint64_t bytes_down = 0;
    std::uint64_t bytes_up = 0;
    std::uint64_t state_hash = 0;
    /// Empty unless the run failed.
    std::string error;
};

/// The p-quantile by nearest rank (0 for none).
double quantile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(v.size())));
    return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
}

server::ServerConfig server_config(const ServerTickOptions& o, int tick_rate_hz) {
    server::ServerConfig cfg;  // the server's defaults, but:
    cfg.max_players = o.bots;
    cfg.min_players = o.bots;
    // jetrace-server's default snapshot rate.
    cfg.snapshot_rate_hz = server::default_snapshot_rate(tick_rate_hz);
    // A race that lasts: no car finishes within the measured time.
    cfg.laps = static_cast<int>(server::ServerLimits::laps.max);
    return cfg;
}

std::vector<std::unique_ptr<Bot>> make_bots(net::MemoryHub& hub, const Scene& scene, int count) {
    const std::vector<DriverSkill> skills = skills_for(count, kSkillSeed);
    std::vector<std::unique_ptr<Bot>> bots;
    for (int i = 0; i < count; ++i) {
        auto b = std::make_unique<Bot>();
        b->pilot = Pilot(skills[static_cast<std::size_t>(i)]);
        b->net = hub.connect();
        client::ClientConfig cc;
        cc.name = "bot" + std::to_string(i);
        b->client = std::make_unique<client::RaceClient>(cc, scene, *b->net);
        b->input = std::ref(b->pilot);
        bots.push_back(std::move(b));
    }
    return bots;
}

void step_bots(std::vector<std::unique_ptr<Bot>>& bots, std::uint64_t now_us) {
    for (auto& b : bots) b->client->update(now_us, b->input);
}

/// One fresh race: the lobby and countdown, then `o.seconds` of race time
/// timed. The tick time is the thread CPU time of each RaceServer::update
/// call that stepped a tick (divided among its ticks, if several): the
/// tick, the snapshots it encodes and queues, and that call's handling of
/// the datagrams that arrived in its millisecond. The bots run outside it.
Run run_once(const Scene& scene, const ServerTickOptions& o) {
    Run run;
    net::MemoryHubConfig hc;
    hc.latency_ms = static_cast<std::uint32_t>(o.latency_ms);
    hc.max_connections = static_cast<std::size_t>(o.bots);
    net::MemoryHub hub(hc);
    const std::unique_ptr<net::Transport> server_end = hub.listen();
    const server::ServerConfig cfg = server_config(o, scene.physics.tick_rate_hz);
    server::RaceServer srv(cfg, scene, *server_end);
    std::vector<std::unique_ptr<Bot>> bots = make_bots(hub, scene, o.bots);

    std::uint64_t now_us = 0;
    while (srv.phase() != proto::RacePhase::racing) {
        if (now_us >= kStartLimitUs) {
            run.error = "the race did not start within 60 s (" + std::to_string(srv.players()) + " players joined)";
            return run;
        }
        now_us += kStepUs;
        srv.update(now_us);
        step_bots(bots, now_us);
    }
    const net::Totals before = server_end->totals();
    const auto snapshot_interval = static_cast<std::uint32_t>(scene.physics.tick_rate_hz / cfg.snapshot_rate_hz);
    const auto target = static_cast<std::uint64_t>(std::llround(o.seconds * scene.physics.tick_rate_hz));
    while (run.ticks < target) {
        now_us += kStepUs;
        const CpuTimer timer;
        const int stepped = srv.update(now_us);
        const double us = timer.ns() / 1000.0;
        run.update_us += us;
        for (int k = 0; k < stepped; ++k) run.tick_us.push_back(us / stepped);
        // One tick per 1 ms step at any tick rate up to 1 kHz: it sent
        // snapshots if its tick is a multiple of the snapshot interval.
        if (stepped == 1) {
            (srv.world().tick % snapshot_interval == 0 ? run.snapshot_tick_us : run.plain_tick_us).push_back(us);
        }
        run.ticks += static_cast<std::uint64_t>(stepped);
        step_bots(bots, now_us);
    }
    const net::Totals after = server_end->totals();
    run.bytes_down = after.bytes_sent - before.bytes_sent;
    run.bytes_up = after.bytes_received - before.bytes_received;
    run.state_hash = state_hash(srv.world());
    if (srv.phase() != proto::RacePhase::racing) run.error = "the race ended within the measured time";
    if (srv.players() != o.bots) {
        run.error = std::to_string(o.bots - srv.players()) + " bots left during the race";
    }
    return run;
}

/// Empty if `r` agrees with the first run `first` on everything but the times.
std::string disagreement(const Run& first, const Run& r, int repeat) {
    const auto differs = [&](const char* what, std::uint64_t a, std::uint64_t b) {
        return "repeat " + std::to_string(repeat + 1) + ": " + what + " " + std::to_string(b) + ", run 1: " +
               std::to_string(a);
    };
    if (r.ticks != first.ticks) return differs("ticks", first.ticks, r.ticks);
    if (r.bytes_down != first.bytes_down) return differs("bytes down", first.bytes_down, r.bytes_down);
    if (r.bytes_up != first.bytes_up) return differs("bytes up", first.bytes_up, r.bytes_up);
    if (r.state_hash != first.state_hash) {
        return "repeat " + std::to_string(repeat + 1) + ": state_hash " + hash_hex(r.state_hash) + ", run 1: " +
               hash_hex(first.state_hash);
    }
    return "";
}

void print(const ServerTickOptions& o, const Scene& scene, int snapshot_rate_hz, const std::vector<Run>& runs) {
    std::vector<double> medians, p99s, snapshot_medians, plain_medians, update_us;
    for (const Run& r : runs) {
        medians.push_back(median(r.tick_us));
        p99s.push_back(quantile(r.tick_us, 0.99));
        snapshot_medians.push_back(median(r.snapshot_tick_us));
        plain_medians.push_back(median(r.plain_tick_us));
        update_us.push_back(r.update_us / static_cast<double>(r.ticks));
    }
    const Run& r = runs.front();
    const double client_seconds = o.bots * static_cast<double>(r.ticks) / scene.physics.tick_rate_hz;
    nlohmann::json j;
    j["benchmark"] = "server";
    j["track"] = o.track;
    j["bots"] = o.bots;
    j["seconds"] = o.seconds;
    j["repeats"] = o.repeats;
    j["latency_ms"] = o.latency_ms;
    j["tick_rate_hz"] = scene.physics.tick_rate_hz;
    j["snapshot_rate_hz"] = snapshot_rate_hz;
    j["ticks"] = r.ticks;
    j["tick_us_median"] = median(medians);
    j["tick_us_p99"] = median(p99s);
    j["tick_us_median_runs"] = medians;
    j["tick_us_p99_runs"] = p99s;
    // Half the ticks send snapshots (at 60 of 120 Hz) and cost about twice
    // the others: each kind's median is steadier than the mixed one.
    j["snapshot_tick_us_median"] = median(snapshot_medians);
    j["plain_tick_us_median"] = median(plain_medians);
    // Every update of the window (inputs and acknowledgements handled
    // between ticks too) per tick.
    j["update_us_per_tick"] = median(update_us);
    j["bytes_down"] = r.bytes_down;
    j["bytes_up"] = r.bytes_up;
    j["bytes_down_per_client_per_s"] = static_cast<double>(r.bytes_down) / client_seconds;
    j["bytes_up_per_client_per_s"] = static_cast<double>(r.bytes_up) / client_seconds;
    j["state_hash"] = hash_hex(r.state_hash);
    std::printf("%s\n", j.dump().c_str());
}

}  // namespace

CLI::App* add_server_tick(CLI::App& app, ServerTickOptions& o) {
    auto* sub = app.add_subcommand("server", "the server's tick and wire bytes per client: AI bots over an in-memory network");
    sub->add_option("--track", o.track, "a built-in track")->check(CLI::IsMember(builtin_track_names()));
    sub->add_option("--bots", o.bots, "AI bots, each a predicting client on its own connection")
        ->check(CLI::Range(1, proto::kMaxSlots));
    sub->add_option("--seconds", o.seconds, "race time measured after the start (s)")
        ->check(cli::finite() & CLI::Range(0.1, 600.0));
    sub->add_option("--repeats", o.repeats, "timed runs; medians of the times are reported, the bytes and hash must agree")
        ->check(CLI::Range(1, 50));
    sub->add_option("--latency-ms", o.latency_ms, "one-way latency of the in-memory network (ms)")
        ->check(CLI::Range(0, 1000));
    cli::add_log_level_option(*sub, o.log_level);
    return sub;
}

int run_server_tick(const ServerTickOptions& o) {
    cli::log_to_stderr("jetrace-bench", o.log_level);
    Track track;
    if (!make_builtin_track(o.track, track)) {
        std::fprintf(stderr, "jetrace-bench server: no built-in track '%s'\n", o.track.c_str());
        return 2;
    }
    const Scene scene = Scene::make(std::move(track), PhysicsSettings{});
    const server::ServerConfig cfg = server_config(o, scene.physics.tick_rate_hz);
    if (const std::string why = server::validate(cfg, scene.physics.tick_rate_hz); !why.empty()) {
        std::fprintf(stderr, "jetrace-bench server: %s\n", why.c_str());
        return 2;
    }
    std::vector<Run> runs;
    for (int i = 0; i < o.repeats; ++i) {
        runs.push_back(run_once(scene, o));
        std::string why = runs.back().error;
        if (why.empty()) why = disagreement(runs.front(), runs.back(), i);
        if (!why.empty()) {
            std::fprintf(stderr, "jetrace-bench server: %s\n", why.c_str());
            return 1;
        }
    }
    print(o, scene, cfg.snapshot_rate_hz, runs);
    return 0;
}

}  // namespace jetrace::bench
