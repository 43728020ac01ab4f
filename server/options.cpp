// jetrace-server's options: parsing, key and track loading, validation.
#include "options.hpp"

#include "jetrace/auth/key_file.hpp"
#include "jetrace/cli/logging.hpp"
#include "jetrace/ops/metrics.hpp"
#include "jetrace/track_io.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace jetrace::server_main {

namespace {

bool fail(const std::string& error) {
    std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
    return false;
}

void add_race_options(CLI::App& app, Options& o) {
    server::ServerConfig& cfg = o.cfg;
    app.add_option("--port", o.net_cfg.port, "UDP port (0: any free port, printed at start)");
    app.add_option("--bind", o.net_cfg.bind, "address to bind");
    app.add_option("--track", o.track_spec, "built-in track (stadium, ring) or a Wavefront .obj file");
    app.add_option("--laps", cfg.laps, "laps per race")->check(CLI::Range(1, 1000));
    app.add_option("--max-players", cfg.max_players, "most players in a race")->check(CLI::Range(1, 64));
    app.add_option("--min-players", cfg.min_players, "players needed to start the countdown")->check(CLI::Range(1, 64));
    app.add_option("--tick-rate", o.tick_rate, "simulation steps per second")->check(CLI::Range(10, 1000));
    app.add_option("--snapshot-rate", cfg.snapshot_rate_hz, "snapshots per second (divides the tick rate)")
        ->check(CLI::Range(1, 1000));
    app.add_option("--races", cfg.races, "exit after this many races (0: host forever)")->check(CLI::Range(0, 1000000));
    app.add_option("--countdown", cfg.countdown_s, "countdown before each race (s)")->check(CLI::Range(0.0, 600.0));
    app.add_option("--finish-window", cfg.finish_window_s, "time the others get after the winner finishes (s)")
        ->check(CLI::Range(1.0, 3600.0));
    app.add_option("--reconnect-grace", cfg.reconnect_grace_s,
                   "how long a dropped player's slot and car wait for its reconnect (s; 0: none)")
        ->check(CLI::Range(0.0, 3600.0));
    app.add_option("--hello-timeout", o.hello_timeout_s,
                   "drop a connection that has not said Hello after this long (s of real time, whatever --time-scale)")
        ->check(CLI::Range(0.1, 600.0));
    app.add_option("--key-file", o.key_file,
                   "private race: admit only connect tokens signed with this key (jetrace-token keygen's FILE.pub)");
    app.add_option("--race-id", cfg.race_id, "private race: connect tokens must name this race (default: none)");
    app.add_option("--results", cfg.results_path, "results JSON file, written atomically at each race's end");
    app.add_option("--record", cfg.record_path, "replay file of the race (jetrace-sim --verify checks it)");
    app.add_option("--sign-key", o.sign_key_file,
                   "sign each replay with this secret key (jetrace-token keygen's FILE; keep it apart from --key-file's)");
    jetrace::cli::add_log_level_option(app, o.log_level);
    app.add_option("--time-scale", o.time_scale, "run the clock this many times faster than real time (tests)")
        ->check(CLI::Range(0.01, 100.0));
}

struct HostingFlags {
    std::string metrics;
    bool agones = false;
    double health_period_s = 2.0;
    double connect_timeout_s = 30.0;
};

void add_hosting_options(CLI::App& app, HostingFlags& h) {
    app.add_option("--metrics", h.metrics,
                   "serve /metrics (Prometheus), /healthz and /status on ADDR:PORT (PORT alone: 127.0.0.1; 0: any port)");
    app.add_flag("--agones", h.agones,
                 "speak the Agones SDK (sidecar at localhost:AGONES_SDK_HTTP_PORT, default 9358; on by itself when "
                 "that variable is set)");
    app.add_option("--agones-health-period", h.health_period_s, "seconds between Agones Health pings")
        ->check(CLI::Range(0.1, 60.0));
    app.add_option("--agones-connect-timeout", h.connect_timeout_s,
                   "seconds to keep retrying an Agones sidecar that is not up yet or stopped answering")
        ->check(CLI::Range(0.5, 3600.0));
}

bool apply_hosting(const HostingFlags& h, Options& o) {
    std::string error;
    if (!h.metrics.empty() && !ops::parse_host_port(h.metrics, o.metrics_host, o.metrics_port, error)) {
        return fail("--metrics: " + error);
    }
    const char* env = std::getenv("AGONES_SDK_HTTP_PORT");
    if (env == nullptr && !h.agones) return true;
    ops::AgonesConfig a;
    a.health_period_s = h.health_period_s;
    a.connect_timeout_s = h.connect_timeout_s;
    if (env != nullptr) {
        const char* end = env + std::strlen(env);
        const auto [p, ec] = std::from_chars(env, end, a.port);
        if (ec != std::errc{} || p != end || a.port < 1 || a.port > 65535) {
            return fail("AGONES_SDK_HTTP_PORT='" + std::string(env) + "' is not a port in [1, 65535]");
        }
    }
    o.agones = a;
    return true;
}

// --sign-key: the secret key that signs each replay (not the connect-token key).
bool load_sign_key(Options& o) {
    if (o.sign_key_file.empty()) return true;
    if (o.cfg.record_path.empty()) return fail("--sign-key needs --record");
    std::string error;
    auth::LoadedKey key;
    if (!auth::load_key_file(o.sign_key_file, key, error)) return fail(error);
    if (!key.has_secret) return fail("--sign-key needs a secret key file (jetrace-token keygen's FILE, not FILE.pub)");
    o.cfg.replay_sign_key = key.secret;
    return true;
}

bool load_connect_key(Options& o) {
    if (o.key_file.empty()) return o.cfg.race_id.empty() || fail("--race-id needs --key-file");
    std::string error;
    auth::LoadedKey key;
    if (!auth::load_key_file(o.key_file, key, error)) return fail(error);
    if (key.has_secret) spdlog::warn("--key-file holds a secret key: the server needs only its .pub file");
    o.cfg.connect_key = key.public_key;
    return true;
}

}  // namespace

std::optional<int> parse_options(int argc, char** argv, Options& o) {
    CLI::App app{"jetrace-server: hosts hovercar races over UDP (ENet)"};
    o.net_cfg.port = 27910;
    add_race_options(app, o);
    HostingFlags hosting;
    add_hosting_options(app, hosting);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    // The hello timeout waits on the network, whose retransmissions (ENet's)
    // run in real time: on the server's scaled clock it is that many times
    // longer. Unscaled, a Hello retransmitted once by a client at --time-scale
    // 4 could miss it (1.25 s of real time) and the race would wait forever
    // for that player.
    o.cfg.hello_timeout_s = o.hello_timeout_s * o.time_scale;
    jetrace::cli::log_to_stderr("server", o.log_level);
    if (!apply_hosting(hosting, o)) return 2;
    return std::nullopt;
}

bool prepare(Options& o, std::optional<Scene>& scene) {
    if (!load_sign_key(o) || !load_connect_key(o)) return false;
    std::string error;
    Track track;
    if (!load_track(o.track_spec, track, error)) return fail(error);
    PhysicsSettings physics;
    physics.tick_rate_hz = o.tick_rate;
    if (const std::string e = validate(physics); !e.empty()) return fail(e);
    if (const std::string e = server::validate(o.cfg, o.tick_rate); !e.empty()) return fail(e);
    scene = Scene::make(std::move(track), physics);
    o.net_cfg.max_connections = static_cast<std::size_t>(o.cfg.max_players) + 8;  // room to refuse politely
    return true;
}

bool apply_allocation(const ops::GameServerView& gs, const Scene& scene, Options& o, std::string& error) {
    ops::AllocationOptions a;
    if (!ops::parse_allocation(gs.annotations, a, error)) return false;
    // The track is loaded before Ready: an allocation can only confirm it.
    if (a.track && *a.track != scene.track.name && *a.track != o.track_spec) {
        error = "annotation " + std::string(ops::kTrackAnnotation) + "=\"" + *a.track + "\": this server hosts '" +
                scene.track.name + "' (its --track)";
        return false;
    }
    if (a.race_id && !o.cfg.connect_key) {
        error = "annotation " + std::string(ops::kRaceIdAnnotation) + " needs --key-file";
        return false;
    }
    server::ServerConfig cfg = o.cfg;
    cfg.laps = a.laps.value_or(cfg.laps);
    cfg.min_players = a.min_players.value_or(cfg.min_players);
    cfg.race_id = a.race_id.value_or(cfg.race_id);
    if (const std::string e = server::validate(cfg, o.tick_rate); !e.empty()) {
        error = "the allocation's annotations give invalid settings: " + e;
        return false;
    }
    o.cfg = cfg;
    spdlog::info("allocation: {} laps, min {} players{}", cfg.laps, cfg.min_players,
                 cfg.race_id.empty() ? "" : ", race id '" + cfg.race_id + "'");
    return true;
}

}  // namespace jetrace::server_main
