#include "hosting.hpp"

#include "jetrace/cli/finite.hpp"
#include "jetrace/ops/metrics.hpp"

#include <spdlog/spdlog.h>

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace jetrace::server {

void add_hosting_options(CLI::App& app, HostingFlags& h) {
    app.add_option("--metrics", h.metrics,
                   "serve /metrics (Prometheus), /healthz and /status on ADDR:PORT (PORT alone: 127.0.0.1; 0: any port)");
    app.add_flag("--agones", h.agones,
                 "speak the Agones SDK (sidecar at localhost:AGONES_SDK_HTTP_PORT, default 9358; on by itself when "
                 "that variable is set)");
    app.add_option("--agones-health-period", h.health_period_s, "seconds between Agones Health pings")
        ->check(jetrace::cli::finite() & CLI::Range(0.1, 60.0));
    app.add_option("--agones-connect-timeout", h.connect_timeout_s,
                   "seconds to keep retrying an Agones sidecar that is not up yet or stopped answering")
        ->check(jetrace::cli::finite() & CLI::Range(0.5, 3600.0));
}

bool apply_hosting(const HostingFlags& h, Hosting& out) {
    std::string error;
    if (!h.metrics.empty() && !ops::parse_host_port(h.metrics, out.metrics_host, out.metrics_port, error)) {
        std::fprintf(stderr, "jetrace-server: --metrics: %s\n", error.c_str());
        return false;
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
            std::fprintf(stderr, "jetrace-server: AGONES_SDK_HTTP_PORT='%s' is not a port in [1, 65535]\n", env);
            return false;
        }
    }
    out.agones = a;
    return true;
}

bool apply_allocation(const ops::GameServerView& gs, const Scene& scene, const std::string& track_spec,
                      int tick_rate, ServerConfig& cfg, std::string& error) {
    ops::AllocationOptions a;
    if (!ops::parse_allocation(gs.annotations, a, error)) return false;
    if (a.track && *a.track != scene.track.name && *a.track != track_spec) {
        error = "annotation " + std::string(ops::kTrackAnnotation) + "=\"" + *a.track + "\": this server hosts '" +
                scene.track.name + "' (its --track)";
        return false;
    }
    if (a.race_id && !cfg.connect_key) {
        error = "annotation " + std::string(ops::kRaceIdAnnotation) + " needs --key-file";
        return false;
    }
    ServerConfig next = cfg;
    next.laps = a.laps.value_or(next.laps);
    next.min_players = a.min_players.value_or(next.min_players);
    next.race_id = a.race_id.value_or(next.race_id);
    if (const std::string e = validate(next, tick_rate); !e.empty()) {
        error = "the allocation's annotations give invalid settings: " + e;
        return false;
    }
    cfg = next;
    spdlog::info("allocation: {} laps, min {} players{}", cfg.laps, cfg.min_players,
                 cfg.race_id.empty() ? "" : ", race id '" + cfg.race_id + "'");
    return true;
}

}  // namespace jetrace::server
