#include "web_link.hpp"

#include "jetrace/net/condition_spec.hpp"
#include "jetrace/proto/messages.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>

namespace jetrace::server {
namespace {

std::optional<net::SequenceRange> input_ticks(std::span<const std::uint8_t> message) {
    net::SequenceRange r;
    if (!proto::input_batch_ticks(message, r.first, r.last)) return std::nullopt;
    return r;
}

nlohmann::json transport_json(const net::SequenceDelayMeter& meter, const net::Transport* conditioner) {
    const std::vector<double>& d = meter.delays_ms();
    nlohmann::json j;
    j["input_delay_ms"] = {{"n", d.size()}};
    if (!d.empty()) {
        j["input_delay_ms"]["p50"] = net::quantile(d, 0.5);
        j["input_delay_ms"]["p99"] = net::quantile(d, 0.99);
        j["input_delay_ms"]["max"] = net::quantile(d, 1.0);
    }
    if (conditioner) {
        const net::SchedulerStats s = net::conditioner_stats(*conditioner);
        j["sent"] = {{"offered", s.offered}, {"dropped", s.dropped}, {"retransmitted", s.retransmitted}};
    }
    return j;
}

}  // namespace

double default_retransmit_ms(const net::Conditions& c) {
    return std::max(20.0, 1.25 * (2.0 * c.latency_ms + c.jitter_ms));
}

std::optional<net::Conditions> parse_web_link(std::string_view spec, std::string& error) {
    net::Conditions c;
    c.retransmit_ms = -1;  // not given
    if (!net::parse_conditions(spec, c, error)) return std::nullopt;
    if (c.retransmit_ms < 0) c.retransmit_ms = default_retransmit_ms(c);
    return c;
}

WebLink::WebLink(const net::Conditions& conditions)
    : conditions_(conditions), websocket_meter_(input_ticks), webrtc_meter_(input_ticks) {}

net::LinkConditions WebLink::link(net::Delivery delivery, std::uint64_t seed) const {
    net::LinkConditions l;
    l.outgoing = l.incoming = conditions_;
    l.outgoing.seed = seed;
    l.incoming.seed = seed ^ 0x9E3779B97F4A7C15ull;
    l.delivery = delivery;
    return l;
}

std::unique_ptr<net::Transport> WebLink::wrap_websocket(std::unique_ptr<net::Transport> t) {
    auto wrapped = net::condition_link(std::move(t), link(net::Delivery::stream, conditions_.seed), &websocket_meter_);
    websocket_ = wrapped.get();
    return wrapped;
}

std::unique_ptr<net::Transport> WebLink::wrap_webrtc(std::unique_ptr<net::Transport> t) {
    auto wrapped =
        net::condition_link(std::move(t), link(net::Delivery::datagrams, conditions_.seed + 1), &webrtc_meter_);
    webrtc_ = wrapped.get();
    return wrapped;
}

std::string WebLink::report() const {
    nlohmann::json j;
    j["web_link"]["websocket"] = transport_json(websocket_meter_, websocket_);
    if (webrtc_) j["web_link"]["webrtc"] = transport_json(webrtc_meter_, webrtc_);
    return j.dump();
}

}  // namespace jetrace::server
