// Metrics: prometheus-cpp families filled from published samples, and the
// cpp-httplib server of /metrics, /healthz and /status.
#include "jetrace/ops/metrics.hpp"

#include "jetrace/net/mux_transport.hpp"

#include "jetrace/server/race_server.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>
#include <prometheus/counter.h>
#include <prometheus/gauge.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>
#include <prometheus/text_serializer.h>

#include <charconv>
#include <mutex>
#include <thread>

namespace jetrace::ops {

namespace {

using prometheus::Counter;
using prometheus::Gauge;

void advance(Counter& c, std::uint64_t total) {
    const double d = static_cast<double>(total) - c.Value();
    if (d > 0) c.Increment(d);
}

Counter& counter(prometheus::Registry& r, const std::string& name, const std::string& help,
                 const prometheus::Labels& labels = {}) {
    return prometheus::BuildCounter().Name(name).Help(help).Register(r).Add(labels);
}

Gauge& gauge(prometheus::Registry& r, const std::string& name, const std::string& help) {
    return prometheus::BuildGauge().Name(name).Help(help).Register(r).Add({});
}

}  // namespace

struct Metrics::Impl {
    prometheus::Registry registry;
    prometheus::Histogram& tick_seconds = prometheus::BuildHistogram()
                                              .Name("jetrace_tick_duration_seconds")
                                              .Help("Time one simulation tick took, network handling included")
                                              .Register(registry)
                                              .Add({}, prometheus::Histogram::BucketBoundaries{
                                                           0.00005, 0.0001, 0.00025, 0.0005, 0.001, 0.002, 0.004,
                                                           0.00833, 0.016, 0.05});
    Gauge& players = gauge(registry, "jetrace_players", "Connected players (those spectating included)");
    Gauge& spectators = gauge(registry, "jetrace_spectators",
                              "Connected players without a car in the race under way (joined during it)");
    Gauge& observers = gauge(registry, "jetrace_observers", "Connected observers (clients that watch without a car)");
    Gauge& held = gauge(registry, "jetrace_players_held", "Slots held for dropped players who may reconnect");
    Counter& started = counter(registry, "jetrace_races_started_total", "Races whose countdown began");
    Counter& finished = counter(registry, "jetrace_races_finished_total",
                                "Races ended by the rules (all finished, finish window, time limit)");
    Counter& aborted = counter(registry, "jetrace_races_aborted_total",
                               "Races stopped by a shutdown or left by every player");
    Counter& bytes_in = counter(registry, "jetrace_network_bytes_received_total", "UDP bytes received");
    Counter& bytes_out = counter(registry, "jetrace_network_bytes_sent_total", "UDP bytes sent");
    Counter& packets_in = counter(registry, "jetrace_network_packets_received_total", "UDP datagrams received");
    Counter& packets_out = counter(registry, "jetrace_network_packets_sent_total", "UDP datagrams sent");
    Counter& late = counter(registry, "jetrace_inputs_late_total",
                            "Inputs that arrived after their tick was stepped without them");
    Counter& dropped = counter(registry, "jetrace_inputs_dropped_total",
                               "Inputs dropped for being too far ahead of the server tick");
    Counter& missing = counter(registry, "jetrace_inputs_missing_total",
                               "Car-ticks stepped with the previous input because the tick's had not arrived");
    prometheus::Family<Gauge>& players_by_transport = prometheus::BuildGauge()
                                                          .Name("jetrace_transport_players")
                                                          .Help("Connected players, by the transport of their connection")
                                                          .Register(registry);
    Gauge& players_enet = players_by_transport.Add({{"transport", "enet"}});
    Gauge& players_websocket = players_by_transport.Add({{"transport", "websocket"}});
    Gauge& players_webrtc = players_by_transport.Add({{"transport", "webrtc"}});
    prometheus::Family<Counter>& transport_bytes_out = prometheus::BuildCounter()
                                                           .Name("jetrace_transport_bytes_sent_total")
                                                           .Help("Bytes sent, by transport (ENet datagrams, WebSocket frames)")
                                                           .Register(registry);
    prometheus::Family<Counter>& transport_bytes_in = prometheus::BuildCounter()
                                                          .Name("jetrace_transport_bytes_received_total")
                                                          .Help("Bytes received, by transport")
                                                          .Register(registry);
    Counter& enet_out = transport_bytes_out.Add({{"transport", "enet"}});
    Counter& websocket_out = transport_bytes_out.Add({{"transport", "websocket"}});
    Counter& webrtc_out = transport_bytes_out.Add({{"transport", "webrtc"}});
    Counter& enet_in = transport_bytes_in.Add({{"transport", "enet"}});
    Counter& websocket_in = transport_bytes_in.Add({{"transport", "websocket"}});
    Counter& webrtc_in = transport_bytes_in.Add({{"transport", "webrtc"}});
    Gauge& web_sockets = gauge(registry, "jetrace_websocket_sockets", "Open game WebSockets (--web)");
    Gauge& rtc_sessions = gauge(registry, "jetrace_webrtc_sessions", "WebRTC data-channel sessions, pending ones included");
    prometheus::Family<Counter>& rtc_refused = prometheus::BuildCounter()
                                                   .Name("jetrace_webrtc_refused_total")
                                                   .Help("WebRTC offers and datagrams refused, by reason")
                                                   .Register(registry);
    Counter& rtc_bad_offer = rtc_refused.Add({{"reason", "bad_offer"}});
    Counter& rtc_busy = rtc_refused.Add({{"reason", "busy"}});
    Counter& rtc_expired = rtc_refused.Add({{"reason", "pending_expired"}});
    Counter& rtc_rate_limited = rtc_refused.Add({{"reason", "rate_limited"}});
    Counter& rtc_sent_reliably = counter(registry, "jetrace_webrtc_unreliable_sent_reliably_total",
                                    "Unreliable messages over 1072 bytes sent on the reliable data channel instead");
    prometheus::Family<Counter>& web_closed = prometheus::BuildCounter()
                                                  .Name("jetrace_websocket_closed_total")
                                                  .Help("Game WebSockets the server closed, by reason")
                                                  .Register(registry);
    Counter& web_queue_full = web_closed.Add({{"reason", "send_queue_full"}});
    Counter& web_malformed = web_closed.Add({{"reason", "malformed_frame"}});
    prometheus::Family<Counter>& web_refused = prometheus::BuildCounter()
                                                   .Name("jetrace_websocket_refused_total")
                                                   .Help("WebSocket upgrades refused before a socket opened, by reason")
                                                   .Register(registry);
    Counter& web_origin = web_refused.Add({{"reason", "origin"}});
    Counter& web_full = web_refused.Add({{"reason", "full"}});
    Counter& web_pre_hello = web_refused.Add({{"reason", "pre_hello_cap"}});
    Counter& replay_bytes = counter(registry, "jetrace_replay_bytes_written_total", "Replay bytes written");
    Counter& write_errors = counter(registry, "jetrace_write_errors_total", "Files that could not be written whole",
                                    {{"file", "replay"}});
    prometheus::Family<Counter>& refused_family = prometheus::BuildCounter()
                                                      .Name("jetrace_connections_refused_total")
                                                      .Help("Hellos refused, by reason")
                                                      .Register(registry);
    prometheus::Family<Counter>& dropped_family = prometheus::BuildCounter()
                                                      .Name("jetrace_connections_dropped_total")
                                                      .Help("Connections the server dropped, by reason")
                                                      .Register(registry);
    std::vector<Counter*> refused, drops;
    Counter& refused_unallocated = refused_family.Add({{"reason", "unallocated"}});

    mutable std::mutex mutex;  // guards the metrics' coherence and status
    std::string status = "{}";
    httplib::Server http;
    std::thread thread;

    Impl() {
        for (const auto name : server::kRefusalNames) refused.push_back(&refused_family.Add({{"reason", std::string(name)}}));
        for (const auto name : server::kDropReasonNames) drops.push_back(&dropped_family.Add({{"reason", std::string(name)}}));
    }
};

Metrics::Metrics() : impl_(std::make_unique<Impl>()) {}

Metrics::~Metrics() {
    if (impl_->thread.joinable()) {
        impl_->http.stop();
        impl_->thread.join();
    }
}

std::unique_ptr<Metrics> Metrics::serve(const std::string& host, int port, std::string& error) {
    auto m = std::make_unique<Metrics>();
    Metrics* self = m.get();
    httplib::Server& http = m->impl_->http;
    http.new_task_queue = [] { return new httplib::ThreadPool(4); };
    http.set_payload_max_length(4096);
    http.Get("/metrics", [self](const httplib::Request&, httplib::Response& res) {
        res.set_content(self->metrics_text(), "text/plain; version=0.0.4; charset=utf-8");
    });
    http.Get("/healthz", [](const httplib::Request&, httplib::Response& res) { res.set_content("ok\n", "text/plain"); });
    http.Get("/status", [self](const httplib::Request&, httplib::Response& res) {
        res.set_content(self->status_json(), "application/json");
    });
    const int bound = port == 0 ? http.bind_to_any_port(host) : (http.bind_to_port(host, port) ? port : -1);
    if (bound < 0) {
        error = "--metrics: cannot listen on " + host + ":" + std::to_string(port);
        return nullptr;
    }
    m->port_ = bound;
    m->impl_->thread = std::thread([&http] { http.listen_after_bind(); });
    return m;
}

void Metrics::observe_ticks(double seconds_each, int ticks) {
    for (int i = 0; i < ticks; ++i) impl_->tick_seconds.Observe(seconds_each);
}

void Metrics::publish(const MetricsSample& s) {
    nlohmann::json j;
    j["phase"] = s.phase;
    j["race"] = s.race_number;
    j["tick"] = s.race_tick;
    j["server_ticks"] = s.server_ticks;
    j["races_finished"] = s.counters.races_finished;
    j["observers"] = s.observers;
    j["players"] = nlohmann::json::array();
    int connected = 0, spectating = 0, held = 0, websocket = 0, webrtc = 0;
    for (const auto& p : s.players) {
        j["players"].push_back({{"slot", p.slot},
                                {"name", p.name},
                                {"connected", p.connected},
                                {"spectating", p.spectating},
                                {"lap", p.lap},
                                {"finished", p.finished},
                                {"transport", p.transport}});
        websocket += p.connected && p.transport == "websocket" ? 1 : 0;
        webrtc += p.connected && p.transport == "webrtc" ? 1 : 0;
        connected += p.connected ? 1 : 0;
        spectating += p.connected && p.spectating ? 1 : 0;
        held += p.connected ? 0 : 1;
    }
    // Names are validated UTF-8; replace anything else rather than throw.
    std::string status = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    Impl& m = *impl_;
    std::lock_guard lock(m.mutex);
    m.status = std::move(status);
    m.players.Set(connected);
    m.players_enet.Set(connected - websocket - webrtc);
    m.players_websocket.Set(websocket);
    m.players_webrtc.Set(webrtc);
    advance(m.enet_out, s.traffic_enet.bytes_sent);
    advance(m.enet_in, s.traffic_enet.bytes_received);
    advance(m.websocket_out, s.traffic_websocket.bytes_sent);
    advance(m.websocket_in, s.traffic_websocket.bytes_received);
    advance(m.webrtc_out, s.traffic_webrtc.bytes_sent);
    advance(m.webrtc_in, s.traffic_webrtc.bytes_received);
    m.web_sockets.Set(static_cast<double>(s.web.open_sockets));
    advance(m.web_queue_full, s.web.send_queue_drops);
    advance(m.web_malformed, s.web.malformed_drops);
    advance(m.web_origin, s.web.origin_refusals);
    advance(m.web_full, s.web.full_refusals);
    advance(m.web_pre_hello, s.web.pre_hello_refusals);
    m.rtc_sessions.Set(static_cast<double>(s.rtc.sessions_open));
    advance(m.rtc_bad_offer, s.rtc.offers_refused_bad);
    advance(m.rtc_busy, s.rtc.offers_refused_busy);
    advance(m.rtc_expired, s.rtc.pending_expired);
    advance(m.rtc_rate_limited, s.rtc.rate_limited);
    advance(m.rtc_sent_reliably, s.rtc.unreliable_sent_reliably);
    m.spectators.Set(spectating);
    m.observers.Set(s.observers);
    m.held.Set(held);
    advance(m.started, s.counters.races_started);
    advance(m.finished, s.counters.races_finished);
    advance(m.aborted, s.counters.races_aborted);
    advance(m.bytes_in, s.traffic.bytes_received);
    advance(m.bytes_out, s.traffic.bytes_sent);
    advance(m.packets_in, s.traffic.packets_received);
    advance(m.packets_out, s.traffic.packets_sent);
    advance(m.late, s.counters.inputs_late);
    advance(m.dropped, s.counters.inputs_dropped);
    advance(m.missing, s.counters.inputs_missing);
    advance(m.replay_bytes, s.replay_bytes_written);
    advance(m.write_errors, s.replay_failures);
    advance(m.refused_unallocated, s.refused_unallocated);
    for (std::size_t i = 0; i < m.refused.size(); ++i) advance(*m.refused[i], s.counters.refused[i]);
    for (std::size_t i = 0; i < m.drops.size(); ++i) advance(*m.drops[i], s.counters.dropped[i]);
}

std::string Metrics::metrics_text() const {
    std::lock_guard lock(impl_->mutex);
    return prometheus::TextSerializer().Serialize(impl_->registry.Collect());
}

std::string Metrics::status_json() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->status;
}

MetricsSample sample_of(const server::RaceServer& server, const net::Transport& transport) {
    MetricsSample s;
    s.phase = proto::to_string(server.phase());
    s.race_number = server.race_number();
    s.race_tick = server.world().tick;
    s.server_ticks = server.ticks();
    s.players = server.player_status();
    s.observers = server.observers();
    s.counters = server.counters();
    s.traffic = transport.totals();
    s.traffic_enet = net::part_totals(transport, "enet");
    s.traffic_websocket = net::part_totals(transport, "websocket");
    s.traffic_webrtc = net::part_totals(transport, "webrtc");
    return s;
}

bool parse_host_port(const std::string& spec, std::string& host, int& port, std::string& error) {
    std::string port_text = spec;
    host = "127.0.0.1";
    if (const auto colon = spec.rfind(':'); colon != std::string::npos) {
        host = spec.substr(0, colon);
        port_text = spec.substr(colon + 1);
        if (host.size() >= 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
    }
    const auto [end, ec] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
    if (host.empty() || port_text.empty() || ec != std::errc{} || end != port_text.data() + port_text.size() ||
        port < 0 || port > 65535) {
        error = "'" + spec + "' is not PORT or ADDR:PORT with PORT in [0, 65535]";
        return false;
    }
    return true;
}

}  // namespace jetrace::ops
