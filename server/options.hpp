// jetrace-server's command line and the checks it does before listening.
#pragma once

#include "hosting.hpp"
#include "web_host.hpp"
#include "jetrace/net/transport.hpp"
#include "jetrace/server/race_server.hpp"
#include "jetrace/server/replay_recorder.hpp"

#include <string>

namespace jetrace::server {

struct HostOptions {
    ServerConfig cfg;
    net::ServerConfig net_cfg;
    std::string track_spec = "stadium";
    std::string log_level = "info";
    int tick_rate = 120;
    double time_scale = 1.0;
    double hello_timeout_s = 5.0;
    /// --linger, real time (unit: s).
    double linger_s = 5.0;
    double drain_timeout_s = 60.0;
    std::string lobby_timeout_action = "start";
    std::string key_file;
    std::string sign_key_file;
    /// --results (%n and %t expand per race; "" = none).
    std::string results_path;
    /// --record and --sign-key (path_template "" = no replays).
    RecorderConfig recorder;
    /// --nonce-file ("" = spent nonces live in memory only).
    std::string nonce_file;
    /// --metrics and Agones.
    Hosting hosting;
    /// --web: the game page and browser players (none: ENet only).
    std::optional<web::WebConfig> web;
    /// --web without --no-webrtc: browsers' WebRTC data channels.
    std::optional<rtc::RtcConfig> rtc;
    /// --web-link: conditions on browsers' links (none: as they are).
    std::optional<net::Conditions> web_link;
};

/// Parses the command line. -1: go on; else the exit code (0 for --help).
int parse_host_options(int argc, char** argv, HostOptions& o);
/// Keys, spent nonces, and whether the results, replay and nonce files can
/// be created: false with the message printed (exit 2, before listening).
bool prepare_host(HostOptions& o);

}  // namespace jetrace::server
