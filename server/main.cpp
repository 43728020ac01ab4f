// jetrace-server: a dedicated authoritative race server over ENet/UDP, with
// optional hosting around it (server/ops): the Agones SDK and metrics.
#include "options.hpp"

#include "jetrace/net/transport.hpp"
#include "jetrace/ops/metrics.hpp"
#include "jetrace/ops/unallocated_gate.hpp"
#include "jetrace/server/host_files.hpp"
#include "jetrace/server/race_server.hpp"
#include "jetrace/server/replay_recorder.hpp"
#include "jetrace/server/tick_times.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <thread>

namespace {

using namespace jetrace;
using Clock = std::chrono::steady_clock;

std::atomic<int> g_signals{0};
std::atomic<int> g_last_signal{0};
void on_signal(int sig) {
    g_last_signal = sig;
    g_signals.fetch_add(1);
}

const char* signal_reason(int sig) {
    return sig == SIGINT ? "server interrupted" : sig == SIGHUP ? "server hung up" : "server terminated";
}

/// How long Shutdown is retried at exit (unit: s).
constexpr double kAgonesShutdownWait = 3.0;

/// Files lost (each logged with what): a non-zero exit.
struct Losses {
    std::uint32_t results = 0;
    std::uint32_t nonces = 0;
};

/// What the server is hosted with: its socket, and the optional ops parts.
struct Host {
    /// --web-link: the browser links' conditions and input delays (or null);
    /// declared before `transport`, which holds pointers into it.
    std::unique_ptr<server::WebLink> web_link;
    std::unique_ptr<net::Transport> transport;
    /// --web: the WebSocket transport inside `transport`.
    const net::Transport* web = nullptr;
    /// --web: the WebRTC data-channel transport inside `transport` (or null).
    const net::Transport* rtc = nullptr;
    std::unique_ptr<ops::Metrics> metrics;
    std::unique_ptr<ops::AgonesClient> agones;
    /// --record: the replay of each race.
    std::unique_ptr<server::ReplayRecorder> recorder;
    Clock::time_point start = Clock::now();
    double time_scale = 1.0;
    std::uint64_t refused_unallocated = 0;

    std::uint32_t replay_failures() const { return recorder ? recorder->failures() : 0; }
    /// The server's clock: wall time scaled by --time-scale (unit: µs).
    std::uint64_t now_us() const {
        return static_cast<std::uint64_t>(std::chrono::duration<double, std::micro>(Clock::now() - start).count() *
                                          time_scale);
    }
    void publish(const server::RaceServer& srv) {
        if (!metrics) return;
        auto sample = ops::sample_of(srv, *transport);
        sample.refused_unallocated = refused_unallocated;
        sample.replay_failures = replay_failures();
        sample.replay_bytes_written = recorder ? recorder->bytes_written() : 0;
        if (web) sample.web = web::web_stats(*web);
        if (rtc) sample.rtc = rtc::rtc_stats(*rtc);
        metrics->publish(sample);
    }
};

void print_race_end(const server::RaceEnd& end) {
    std::printf("race %u finished after %u ticks (%s)\n", end.race_number, end.ticks,
                replay::end_reason_name(end.reason));
    int pos = 1;
    for (const auto& s : end.standings) {
        std::printf("  %2d. %-16s %s lap %u %.3f s\n", pos++, s.name.c_str(), s.finished ? "finished" : "dnf     ",
                    s.lap, s.finish_time_s);
    }
    std::printf("state_hash=%s\n", hash_hex(end.state_hash).c_str());
    std::fflush(stdout);
}

void attach_files(server::RaceServer& srv, const server::HostOptions& o, const std::string& track, Losses& lost,
                  const server::WebLink* web_link) {
    srv.on_race_end = [&o, track, &lost, web_link](const server::RaceEnd& end) {
        print_race_end(end);
        if (web_link) {
            std::printf("%s\n", web_link->report().c_str());
            std::fflush(stdout);
        }
        std::string error;
        if (!o.results_path.empty() && !server::write_results(o.results_path, end, track, o.cfg.laps, error)) {
            ++lost.results;
            spdlog::error("{}", error);
        }
    };
    if (o.nonce_file.empty()) return;
    srv.on_nonce_spent = [&o, &lost](const auth::TokenVerifier& v) {
        std::string error;
        if (!server::save_nonce_file(o.nonce_file, v.spent(), error)) {
            ++lost.nonces;
            spdlog::error("spent connect-token nonces not saved (a restart would accept those tokens again): {}", error);
        }
    };
}

/// The track, validated settings and the scene; false after printing why.
bool make_scene(server::HostOptions& o, std::optional<Scene>& scene) {
    std::string error;
    Track track;
    if (!load_track(o.track_spec, track, error)) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return false;
    }
    PhysicsSettings physics;
    physics.tick_rate_hz = o.tick_rate;
    std::string invalid = validate(physics);
    if (invalid.empty()) invalid = server::validate(o.cfg, o.tick_rate);
    if (!invalid.empty()) {
        std::fprintf(stderr, "jetrace-server: %s\n", invalid.c_str());
        return false;
    }
    scene = Scene::make(std::move(track), physics);
    // Room to refuse politely beyond the players and observers.
    o.net_cfg.max_connections = static_cast<std::size_t>(o.cfg.max_players) + static_cast<std::size_t>(o.cfg.max_observers) + 8;
    return true;
}

/// Binds the game port and the metrics port, prints them, starts Agones
/// (whose first call is Ready: the track is loaded and the ports bound).
bool open_host(const server::HostOptions& o, Host& host) {
    std::string error;
    host.time_scale = o.time_scale;
    host.transport = net::listen_enet(o.net_cfg, error);
    if (!host.transport) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return false;
    }
    std::printf("listening on %s:%u\n", o.net_cfg.bind.c_str(), host.transport->local_port());
    if (o.web) {
        if (o.web_link) host.web_link = std::make_unique<server::WebLink>(*o.web_link);
        host.transport =
            server::open_web(*o.web, o.rtc, std::move(host.transport), host.web, host.rtc, host.web_link.get());
        if (!host.transport) return false;
    }
    if (!o.hosting.metrics_host.empty()) {
        host.metrics = ops::Metrics::serve(o.hosting.metrics_host, o.hosting.metrics_port, error);
        if (!host.metrics) {
            std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
            return false;
        }
        std::printf("metrics on %s:%d\n", o.hosting.metrics_host.c_str(), host.metrics->port());
        host.metrics->publish(ops::MetricsSample{});
    }
    if (o.cfg.connect_key) spdlog::info("private race: only players with a connect token signed with the key get in");
    std::fflush(stdout);
    if (o.hosting.agones) {
        host.agones = std::make_unique<ops::AgonesClient>(*o.hosting.agones);
        host.agones->start();
    }
    return true;
}

/// Until Agones allocates the server: refuse players, keep Health going.
/// 0 once allocated (race options applied), else the exit code.
int wait_for_allocation(const Scene& scene, server::HostOptions& o, Host& host) {
    // On the server's (scaled) clock, as RaceServer's hello timeout.
    ops::UnallocatedGate gate(static_cast<std::uint64_t>(o.cfg.hello_timeout_s * 1000));
    spdlog::info("waiting for the Agones allocation (players are refused until then)");
    for (;;) {
        host.agones->heartbeat();
        gate.service(*host.transport, host.now_us() / 1000);
        if (host.metrics && gate.refused() != host.refused_unallocated) {
            host.refused_unallocated = gate.refused();
            ops::MetricsSample s;
            s.refused_unallocated = host.refused_unallocated;
            s.traffic = host.transport->totals();
            host.metrics->publish(s);
        }
        if (g_signals != 0) {
            spdlog::info("server stopping before its allocation (signal {})", g_last_signal.load());
            return 0;
        }
        if (!host.agones->failure().empty()) return 1;
        if (const auto gs = host.agones->allocation()) {
            gate.close_all(*host.transport);
            std::string error;
            if (server::apply_allocation(*gs, scene, o.track_spec, o.tick_rate, o.cfg, error)) return 0;
            spdlog::error("bad allocation: {}; shutting down", error);
            return 2;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

/// Runs until the server is done; signals drain it, a second one stops it.
/// 1 if Agones was lost, else 0.
int run(server::RaceServer& srv, Host& host, const server::HostOptions& o, server::TickTimes& tick_ms) {
    int handled = 0, rc = 0;
    while (!srv.done()) {
        const int signals = g_signals.load();
        if (signals > handled) {
            handled = signals;
            srv.drain(signal_reason(g_last_signal), o.drain_timeout_s * o.time_scale);
        }
        if (host.agones) {
            host.agones->heartbeat();
            if (!host.agones->failure().empty() && rc == 0) {
                srv.shutdown("the server lost its Agones sidecar");
                rc = 1;
            }
        }
        const auto t0 = Clock::now();
        // Connect tokens expire by the wall clock, whatever the time scale.
        const auto unix_s = std::chrono::duration_cast<std::chrono::seconds>(
                                std::chrono::system_clock::now().time_since_epoch()).count();
        const int ticks = srv.update(host.now_us(), static_cast<std::int64_t>(unix_s));
        if (ticks > 0) {
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / ticks;
            tick_ms.add(ms, static_cast<std::uint64_t>(ticks));
            if (host.metrics) host.metrics->observe_ticks(ms / 1000.0, ticks);
            host.publish(srv);
        }
        std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    // Let goodbyes leave.
    std::vector<net::Event> ignored;
    for (int i = 0; i < 20; ++i) {
        host.transport->service(host.now_us() / 1000, ignored);
        host.transport->flush();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    host.publish(srv);
    return rc;
}

/// One JSON line of figures; rates per simulated second.
void print_figures(const server::RaceServer& srv, const Host& host, const server::TickTimes& tick_ms,
                   const Losses& lost) {
    const double wall_s = std::chrono::duration<double>(Clock::now() - host.start).count() * host.time_scale;
    const auto totals = host.transport->totals();
    nlohmann::json j;
    j["races"] = srv.races_completed();
    j["ticks"] = srv.ticks();
    j["tick_ms_median"] = tick_ms.percentile(0.5);
    j["tick_ms_p99"] = tick_ms.percentile(0.99);
    j["max_players"] = srv.max_players_seen();
    j["bytes_sent_per_s"] = static_cast<double>(totals.bytes_sent) / wall_s;
    j["bytes_received_per_s"] = static_cast<double>(totals.bytes_received) / wall_s;
    j["wall_s"] = wall_s;
    j["replay_failures"] = host.replay_failures();
    j["results_failures"] = lost.results;
    j["nonce_failures"] = lost.nonces;
    std::printf("%s\n", j.dump().c_str());
}

}  // namespace

int main(int argc, char** argv) {
    server::HostOptions o;
    if (const int rc = server::parse_host_options(argc, argv, o); rc >= 0) return rc;
    if (!server::prepare_host(o)) return 2;
    std::optional<Scene> scene;
    if (!make_scene(o, scene)) return 2;
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) std::signal(sig, on_signal);
    Host host;
    if (!open_host(o, host)) return 1;
    if (host.agones) {
        const int rc = wait_for_allocation(*scene, o, host);
        if (rc != 0 || g_signals != 0) {
            host.agones->shutdown(kAgonesShutdownWait);
            return rc;
        }
    }
    server::RaceServer srv(o.cfg, *scene, *host.transport);
    if (!o.recorder.path_template.empty()) {
        host.recorder = std::make_unique<server::ReplayRecorder>(o.recorder);
        srv.observer = host.recorder.get();
    }
    Losses lost;
    attach_files(srv, o, scene->track.name, lost, host.web_link.get());
    server::TickTimes tick_ms;
    const int rc = run(srv, host, o, tick_ms);
    // After the last race (or a signal): the GameServer is done.
    if (host.agones) host.agones->shutdown(kAgonesShutdownWait);
    print_figures(srv, host, tick_ms, lost);
    if (rc != 0) return rc;
    // A replay, results or nonce table that could not be written is lost data.
    return host.replay_failures() + lost.results + lost.nonces == 0 ? 0 : 1;
}
