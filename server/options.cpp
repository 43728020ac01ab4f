// jetrace-server's command line.
#include "options.hpp"

#include "jetrace/auth/key_file.hpp"
#include "jetrace/cli/finite.hpp"
#include "jetrace/cli/logging.hpp"
#include "jetrace/cli/range.hpp"
#include "jetrace/server/host_files.hpp"
#include "jetrace/server/path_template.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <set>

namespace jetrace::server {

namespace {

const CLI::Validator kFinite = jetrace::cli::finite();
using L = ServerLimits;
using jetrace::cli::in_range;

void add_race_options(CLI::App& app, HostOptions& o) {
    ServerConfig& cfg = o.cfg;
    app.add_option("--port", o.net_cfg.port, "UDP port (0: any free port, printed at start)");
    app.add_option("--bind", o.net_cfg.bind, "address to bind");
    app.add_option("--pre-hello-limit", o.net_cfg.max_pending_per_address,
                   "most connections one IP address may hold before their Hello; further requests are refused "
                   "(close code 2008, the client may try again) (0: no limit)")
        ->check(CLI::Range(0, 1000));
    app.add_option("--track", o.track_spec, "built-in track (stadium, ring) or a Wavefront .obj file");
    app.add_option("--laps", cfg.laps, "laps per race")->check(in_range(L::laps));
    app.add_option("--max-players", cfg.max_players, "most players in a race")->check(in_range(L::players));
    app.add_option("--max-observers", cfg.max_observers,
                   "most observers (clients that watch without a car) at a time, on top of the players")
        ->check(in_range(L::observers));
    app.add_option("--min-players", cfg.min_players, "players needed to start the countdown")->check(in_range(L::players));
    app.add_option("--tick-rate", o.tick_rate, "simulation steps per second (clients adopt it)")
        ->check(CLI::Range(10, 1000));
    app.add_option("--snapshot-rate", cfg.snapshot_rate_hz,
                   "snapshots per second; divides the tick rate (default: its largest divisor up to 60)")
        ->check(CLI::Range(1, 1000));
    app.add_option("--races", cfg.races, "exit after this many races (0: host forever)")->check(in_range(L::races));
    app.add_option("--countdown", cfg.countdown_s, "countdown before each race (s)")
        ->check(in_range(L::countdown_s));
    app.add_option("--finish-window", cfg.finish_window_s, "time the others get after the winner finishes (s)")
        ->check(in_range(L::finish_window_s));
    app.add_option("--reconnect-grace", cfg.reconnect_grace_s,
                   "how long a dropped player's slot and car wait for its reconnect (s; 0: none)")
        ->check(in_range(L::reconnect_grace_s));
    app.add_option("--input-hold", cfg.input_hold_s,
                   "a player's missing input repeats its last one this long, then the car gets neutral inputs (s)")
        ->check(in_range(L::input_hold_s));
    app.add_option("--hello-timeout", o.hello_timeout_s,
                   "drop a connection that has not said Hello after this long (s of real time, whatever --time-scale)")
        ->check(in_range(L::hello_timeout_s));
    app.add_option("--linger", o.linger_s,
                   "after the last race (or a stop), keep serving until every client has its Results and Goodbye "
                   "or has left, at most this long (s of real time, whatever --time-scale; 0: exit at once)")
        ->check(in_range(L::linger_s));
    app.add_option("--lobby-timeout", cfg.lobby_timeout_s,
                   "with 1 to --min-players - 1 players for this long, start anyway or cancel (s; 0: wait forever)")
        ->check(in_range(L::lobby_timeout_s));
    app.add_option("--lobby-timeout-action", o.lobby_timeout_action,
                   "what the lobby timeout does: start (the race, with those there) or cancel (tell them and reset)")
        ->check(CLI::IsMember({"start", "cancel"}));
    app.add_option("--drain-timeout", o.drain_timeout_s,
                   "on SIGTERM/SIGINT/SIGHUP, let the race under way finish this long before cutting it short (s)")
        ->check(kFinite)->check(CLI::Range(0.0, 86400.0));
}

void add_file_options(CLI::App& app, HostOptions& o) {
    app.add_option("--key-file", o.key_file,
                   "private race: admit only connect tokens signed with this key (jetrace-token keygen's FILE.pub)");
    app.add_option("--race-id", o.cfg.race_id, "private race: connect tokens must name this race (default: none)");
    app.add_option("--nonce-file", o.nonce_file,
                   "private race: keep spent connect-token nonces in this file across restarts");
    app.add_option("--results", o.results_path,
                   "results JSON of each race, written atomically (%n: race number, %t: UTC start time)");
    app.add_option("--record", o.recorder.path_template, "replay file of each race (%n, %t as for --results)");
    app.add_option("--sign-key", o.sign_key_file,
                   "sign each replay with this secret key (jetrace-token keygen's FILE; keep it apart from --key-file's)");
    jetrace::cli::add_log_level_option(app, o.log_level);
    app.add_option("--time-scale", o.time_scale, "run the clock this many times faster than real time (tests)")
        ->check(kFinite)->check(CLI::Range(0.01, 100.0));
}

bool fail(const std::string& error) {
    std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
    return false;
}

bool load_keys(HostOptions& o) {
    std::string error;
    if (!o.sign_key_file.empty()) {
        auth::LoadedKey key;
        if (o.recorder.path_template.empty()) return fail("--sign-key needs --record");
        if (!auth::load_key_file(o.sign_key_file, key, error)) return fail(error);
        if (!key.has_secret) return fail("--sign-key needs a secret key file (jetrace-token keygen's FILE, not FILE.pub)");
        o.recorder.sign_key = key.secret;
    }
    if (o.key_file.empty()) {
        if (!o.cfg.race_id.empty()) return fail("--race-id needs --key-file");
        if (!o.nonce_file.empty()) return fail("--nonce-file needs --key-file");
        return true;
    }
    auth::LoadedKey key;
    if (!auth::load_key_file(o.key_file, key, error)) return fail(error);
    if (key.has_secret) spdlog::warn("--key-file holds a secret key: the server needs only its .pub file");
    o.cfg.connect_key = key.public_key;
    return true;
}

bool load_nonces(HostOptions& o) {
    if (o.nonce_file.empty()) return true;
    std::string error;
    if (!load_nonce_file(o.nonce_file, o.cfg.spent_nonces, error)) return fail(error);
    std::set<auth::Nonce> seen;
    for (const auth::SpentNonce& s : o.cfg.spent_nonces) {
        if (!seen.insert(s.nonce).second) return fail("nonce file '" + o.nonce_file + "' is corrupt: a nonce repeats");
    }
    if (o.cfg.spent_nonces.size() > o.cfg.max_connect_nonces) {
        return fail("nonce file '" + o.nonce_file + "' holds more nonces than the server remembers (" +
                    std::to_string(o.cfg.max_connect_nonces) + ")");
    }
    spdlog::info("{} spent connect-token nonces loaded from '{}'", o.cfg.spent_nonces.size(), o.nonce_file);
    return true;
}

}  // namespace

int parse_host_options(int argc, char** argv, HostOptions& o) {
    CLI::App app{"jetrace-server: hosts hovercar races over UDP (ENet)"};
    o.net_cfg.port = 27910;
    o.net_cfg.max_pending_per_address = 4;
    add_race_options(app, o);
    add_file_options(app, o);
    HostingFlags hosting;
    add_hosting_options(app, hosting);
    WebFlags web;
    add_web_options(app, web);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    if (app.count("--snapshot-rate") == 0) o.cfg.snapshot_rate_hz = default_snapshot_rate(o.tick_rate);
    o.cfg.lobby_timeout_cancels = o.lobby_timeout_action == "cancel";
    // The hello timeout waits on the network, whose retransmissions (ENet's)
    // run in real time: on the server's scaled clock it is that many times
    // longer.
    o.cfg.hello_timeout_s = o.hello_timeout_s * o.time_scale;
    if (!ServerLimits::hello_timeout_s.contains(o.cfg.hello_timeout_s)) {
        std::fprintf(stderr, "jetrace-server: --hello-timeout %g times --time-scale %g is %g s of the server's clock: "
                     "it must be in %s\n", o.hello_timeout_s, o.time_scale, o.cfg.hello_timeout_s,
                     ServerLimits::hello_timeout_s.text().c_str());
        return 2;
    }
    // Delivery runs on the network's real time too.
    o.cfg.linger_s = o.linger_s * o.time_scale;
    if (!ServerLimits::linger_s.contains(o.cfg.linger_s)) {
        std::fprintf(stderr, "jetrace-server: --linger %g times --time-scale %g is %g s of the server's clock: "
                     "it must be in %s\n", o.linger_s, o.time_scale, o.cfg.linger_s,
                     ServerLimits::linger_s.text().c_str());
        return 2;
    }
    jetrace::cli::log_to_stderr("server", o.log_level);
    if (!apply_hosting(hosting, o.hosting)) return 2;
    if (!apply_web(web, o.net_cfg.max_pending_per_address, o.web, o.rtc, o.web_link)) return 2;
    return -1;
}

bool prepare_host(HostOptions& o) {
    if (!load_keys(o) || !load_nonces(o)) return false;
    if (o.cfg.lobby_timeout_cancels && o.cfg.lobby_timeout_s <= 0) return fail("--lobby-timeout-action cancel needs --lobby-timeout");
    const auto now = std::chrono::duration_cast<std::chrono::seconds>(
                         std::chrono::system_clock::now().time_since_epoch()).count();
    std::string error;
    for (const std::string* p : {&o.results_path, &o.recorder.path_template, &o.nonce_file}) {
        if (p->empty()) continue;
        if (!check_can_create(expand_path(*p, 1, now), error)) return fail(error);
    }
    return true;
}

}  // namespace jetrace::server
