// jetrace-server's web port (--web ADDR:PORT): the game page and the
// WebSocket transport beside the ENet socket (server/web, docs/BROWSER.md).
#pragma once

#include "jetrace/net/transport.hpp"
#include "jetrace/rtc/rtc_transport.hpp"
#include "jetrace/web/web_transport.hpp"
#include "web_link.hpp"

#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace jetrace::server {

struct WebFlags {
    /// --web ADDR:PORT ("": no web port).
    std::string web;
    std::vector<std::string> origins;
    std::size_t max_sockets = web::WebConfig{}.max_sockets;
    std::string cert_file, key_file;
    /// --webrtc-port (-1: the web port's number, on UDP), --webrtc-address,
    /// --webrtc-candidate-port (0: the bound port), --no-webrtc.
    int webrtc_port = -1;
    std::string webrtc_address;
    int webrtc_candidate_port = 0;
    bool no_webrtc = false;
    /// --web-link SPEC ("": browsers' links as they are).
    std::string web_link;
};

void add_web_options(CLI::App& app, WebFlags& f);
/// Parses the flags into `out` and `rtc` (nullopt: no --web, or
/// --no-webrtc) and `link` (--web-link); false after printing what is
/// wrong. `pending_cap` is the ENet transport's pre-Hello cap.
bool apply_web(const WebFlags& f, std::size_t pending_cap, std::optional<web::WebConfig>& out,
               std::optional<rtc::RtcConfig>& rtc, std::optional<net::Conditions>& link);

/// Opens the web port and the WebRTC data channels' UDP port (`rtc`, if
/// set) and combines them with `enet`: the server's transport. Prints where
/// the page is; nullptr after printing why it cannot. `web_part` is the web
/// transport inside the result (for its counters), `rtc_part` the WebRTC one.
/// With `link` (may be null) both browser transports are conditioned by it.
std::unique_ptr<net::Transport> open_web(web::WebConfig config, const std::optional<rtc::RtcConfig>& rtc,
                                         std::unique_ptr<net::Transport> enet, const net::Transport*& web_part,
                                         const net::Transport*& rtc_part, WebLink* link);

}  // namespace jetrace::server
