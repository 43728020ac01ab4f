// jetrace-server's --metrics endpoint: /metrics (Prometheus text format, by
// prometheus-cpp), /healthz and /status (JSON), served by cpp-httplib on a
// thread of its own. The tick loop publishes a MetricsSample after its
// updates; the HTTP handlers read only what was published (under a mutex),
// never the RaceServer.
#pragma once

#include "jetrace/net/transport.hpp"
#include "jetrace/rtc/rtc_transport.hpp"
#include "jetrace/web/web_transport.hpp"
#include "jetrace/server/counters.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace jetrace::server {
class RaceServer;
}

namespace jetrace::ops {

/// What the loop publishes: a copy, so the HTTP thread never reads live state.
struct MetricsSample {
    /// "unallocated" (waiting for Agones), "lobby", "countdown", "racing", "finished".
    std::string phase = "unallocated";
    std::uint32_t race_number = 0;
    /// The race's tick (unit: ticks).
    std::uint32_t race_tick = 0;
    /// Ticks stepped since start (unit: ticks).
    std::uint64_t server_ticks = 0;
    std::vector<server::PlayerStatus> players;
    /// Connected observers (unit: clients).
    int observers = 0;
    server::RaceCounters counters;
    /// Replays whose writing failed, and the bytes of every replay so far
    /// (jetrace-server's ReplayRecorder; 0 without --record).
    std::uint64_t replay_failures = 0;
    std::uint64_t replay_bytes_written = 0;
    /// Hellos refused because Agones had not allocated the server yet.
    std::uint64_t refused_unallocated = 0;
    net::Totals traffic;
    /// The traffic of each transport: ENet, the WebSocket and the WebRTC
    /// data channel ones (zeros without --web).
    net::Totals traffic_enet, traffic_websocket, traffic_webrtc;
    /// The WebSocket transport's counters (zeros without --web).
    web::WebStats web;
    /// The WebRTC transport's counters (zeros without it).
    rtc::RtcStats rtc;
};

/// The RaceServer's and the transport's figures now.
MetricsSample sample_of(const server::RaceServer& server, const net::Transport& transport);

class Metrics {
public:
    /// Binds host:port (port 0: any free port) and serves; nullptr and
    /// `error` if it cannot bind.
    static std::unique_ptr<Metrics> serve(const std::string& host, int port, std::string& error);
    /// Not serving: for rendering only (tests).
    Metrics();
    ~Metrics();
    Metrics(const Metrics&) = delete;
    Metrics& operator=(const Metrics&) = delete;

    /// The bound port.
    int port() const { return port_; }
    /// `ticks` ticks that took `seconds_each` each.
    void observe_ticks(double seconds_each, int ticks);
    /// Replaces the published state (counters advance to the sample's).
    void publish(const MetricsSample& sample);

    /// The bodies of /metrics and /status.
    std::string metrics_text() const;
    std::string status_json() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    int port_ = 0;
};

/// Splits "ADDR:PORT", "[V6ADDR]:PORT" or "PORT" (then ADDR is 127.0.0.1).
/// False and `error` unless PORT is an integer in [0, 65535] and ADDR is
/// non-empty.
bool parse_host_port(const std::string& spec, std::string& host, int& port, std::string& error);

}  // namespace jetrace::ops
