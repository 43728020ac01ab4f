// jetrace-server's hosting options (server/ops): --metrics and the Agones
// SDK (--agones or AGONES_SDK_HTTP_PORT), and an allocation's annotations
// applied to the race options (docs/HOSTING.md lists them).
#pragma once

#include "jetrace/ops/agones_client.hpp"
#include "jetrace/server/race_server.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace jetrace::server {

struct HostingFlags {
    std::string metrics;
    bool agones = false;
    /// (unit: s).
    double health_period_s = 2.0;
    /// (unit: s).
    double connect_timeout_s = 30.0;
};

struct Hosting {
    /// --metrics ADDR:PORT, parsed ("" host: no metrics).
    std::string metrics_host;
    int metrics_port = 0;
    /// Set when Agones is on (AGONES_SDK_HTTP_PORT or --agones).
    std::optional<ops::AgonesConfig> agones;
};

void add_hosting_options(CLI::App& app, HostingFlags& h);
/// Parses the flags and AGONES_SDK_HTTP_PORT into `out`; false after printing what is wrong.
bool apply_hosting(const HostingFlags& h, Hosting& out);

/// Applies an allocation's annotations to `cfg` (the track, loaded before
/// Ready, can only be confirmed); false and `error` if one is bad or the
/// result does not validate.
bool apply_allocation(const ops::GameServerView& gs, const Scene& scene, const std::string& track_spec,
                      int tick_rate, ServerConfig& cfg, std::string& error);

}  // namespace jetrace::server
