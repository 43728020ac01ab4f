// jetrace-server's command line, and the set-up that can fail before the
// server listens (keys, track, validation): exit code 2 and a message.
#pragma once

#include "jetrace/net/transport.hpp"
#include "jetrace/ops/agones_client.hpp"
#include "jetrace/server/race_server.hpp"

#include <optional>
#include <string>

namespace jetrace::server_main {

struct Options {
    server::ServerConfig cfg;
    net::ServerConfig net_cfg;
    std::string track_spec = "stadium";
    std::string log_level = "info";
    int tick_rate = 120;
    double time_scale = 1.0;
    double hello_timeout_s = 5.0;
    std::string key_file;
    std::string sign_key_file;
    /// --metrics ADDR:PORT, parsed ("" host: no metrics).
    std::string metrics_host;
    int metrics_port = 0;
    /// Set when Agones is on (AGONES_SDK_HTTP_PORT or --agones).
    std::optional<ops::AgonesConfig> agones;
};

/// Parses argv (and AGONES_SDK_HTTP_PORT) into `o`; an exit code if the
/// program should stop here (--help: 0, bad arguments: non-zero).
std::optional<int> parse_options(int argc, char** argv, Options& o);

/// Loads the key files and the track and validates the settings; false
/// after printing what is wrong.
bool prepare(Options& o, std::optional<Scene>& scene);

/// Applies an allocation's annotations to `o.cfg` (docs/HOSTING.md lists
/// them); false and `error` if one is bad or the result does not validate.
bool apply_allocation(const ops::GameServerView& gs, const Scene& scene, Options& o, std::string& error);

}  // namespace jetrace::server_main
