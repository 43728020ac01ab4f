#include "jetrace/rtc/rtc_transport.hpp"

#include "rate_limits.hpp"
#include "rtc_session.hpp"
#include "signal_state.hpp"

#include "jetrace/webrtc/dtls.hpp"
#include "jetrace/webrtc/stun.hpp"

#include <arpa/inet.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <map>

namespace jetrace::rtc {

namespace {

using detail::Endpoint;
using detail::RtcSession;

/// Datagrams read per service() at most, so a flood cannot hold a tick.
constexpr int kMaxDatagramsPerService = 4096;
/// After disconnect(), queued reliable messages (Goodbye) get this long (unit: ms).
constexpr std::uint64_t kCloseGraceMs = 1000;
/// DTLS content type 22: handshake (ClientHello and later flights).
constexpr std::uint8_t kDtlsHandshake = 22;

class RtcTransport final : public net::Transport {
public:
    RtcTransport(const RtcConfig& config, std::unique_ptr<webrtc::DtlsContext> context)
        : config_(config),
          context_(std::move(context)),
          next_peer_(config.peer_base),
          stun_limits_(config.stun_per_s, config.stun_burst),
          handshake_limits_(config.handshake_per_s, config.handshake_burst) {}
    ~RtcTransport() override {
        if (signal_) signal_->close();
    }

    bool open(std::shared_ptr<RtcSignal>& signal, std::string& error) {
        if (!socket_.open(config_.bind, config_.port, error)) return false;
        signal_ = std::make_shared<detail::SignalState>(config_, context_->fingerprint(), socket_.port());
        signal = signal_;
        return true;
    }

    void service(std::uint64_t now_ms, std::vector<net::Event>& events) override {
        if (now_ms > now_) webrtc::SctpAssociation::advance_timers(static_cast<std::uint32_t>(now_ms - now_));
        now_ = std::max(now_, now_ms);
        for (detail::PendingOffer& p : signal_->take_inbox()) add(std::move(p));
        read_socket();
        for (auto it = sessions_.begin(); it != sessions_.end();) {
            if (step(it->second, events)) it = end(it, events);
            else ++it;
        }
        stun_limits_.prune(now_);
        handshake_limits_.prune(now_);
    }

    bool send(net::PeerId peer, net::Channel channel, std::span<const std::uint8_t> data) override {
        const auto it = sessions_.find(peer);
        if (it == sessions_.end() || !it->second.connected || it->second.closing) return false;
        RtcSession& s = it->second;
        if (data.size() > kMaxReliableBytes) return false;
        // Too large for one unfragmented datagram (a keyframe snapshot of
        // a big race): sent whole on the reliable channel instead.
        if (channel == net::Channel::unreliable && data.size() > kMaxUnreliableBytes) {
            signal_->count_sent_reliably();
            channel = net::Channel::reliable;
        }
        const auto stream = s.streams[static_cast<int>(channel)];
        if (!stream || s.channels->send(*stream, data) != webrtc::SctpSendResult::kSent) return false;
        flush_session(s);
        return true;
    }

    void disconnect(net::PeerId peer) override {
        const auto it = sessions_.find(peer);
        if (it == sessions_.end() || it->second.closing) return;
        it->second.closing = true;
        it->second.closing_ms = now_;
    }

    void flush() override {
        for (auto& [peer, s] : sessions_) flush_session(s);
    }
    net::PeerStats peer_stats(net::PeerId) const override { return {}; }
    net::Totals totals() const override { return totals_; }
    std::uint16_t local_port() const override { return socket_.port(); }
    RtcStats stats() const { return signal_->stats(); }

private:
    void add(detail::PendingOffer&& p) {
        RtcSession s;
        s.peer = next_peer_++;
        s.address = std::move(p.address);
        s.ice = std::move(p.ice);
        s.offer = std::move(p.offer);
        s.created_ms = s.last_received_ms = now_;
        by_ufrag_[s.ice.ufrag] = s.peer;
        sessions_.emplace(s.peer, std::move(s));
    }

    void read_socket() {
        std::uint64_t limited = 0;
        for (int i = 0; i < kMaxDatagramsPerService; ++i) {
            Endpoint from;
            const long n = socket_.receive(buffer_, from);
            if (n < 0) break;
            totals_.bytes_received += static_cast<std::uint64_t>(n);
            ++totals_.packets_received;
            const std::span<const std::uint8_t> d(buffer_.data(), static_cast<std::size_t>(n));
            if (webrtc::is_stun(d)) {
                if (!stun_limits_.allow(from.ip_key(), now_)) ++limited;
                else on_stun(d, from);
            } else if (webrtc::is_dtls(d)) {
                on_dtls(d, from, limited);
            }
        }
        if (limited > 0) signal_->count_rate_limited(limited);
    }

    void on_stun(std::span<const std::uint8_t> d, const Endpoint& from) {
        webrtc::StunMessage m;
        if (webrtc::parse_binding_request(d, m) != webrtc::StunError::kNone) return;
        std::string_view ours, theirs;
        if (!webrtc::split_ice_username(*m.username, ours, theirs)) return;
        const auto u = by_ufrag_.find(std::string(ours));
        if (u == by_ufrag_.end()) return;
        const auto found = sessions_.find(u->second);
        if (found == sessions_.end()) return;
        RtcSession& s = found->second;
        if (theirs != s.offer.ice_ufrag || s.closing || !webrtc::integrity_valid(d, m, s.ice.pwd)) return;
        if (!s.remote || (!s.connected && m.use_candidate && s.remote->key() != from.key())) bind(s, from);
        // Consent checks (RFC 7675, every few seconds) keep a quiet session alive.
        if (s.remote->key() == from.key()) s.last_received_ms = now_;
        if (!s.channels) {
            webrtc::SctpSettings sctp;
            sctp.max_message_bytes = kMaxReliableBytes;
            s.channels = std::make_unique<webrtc::DataChannelSession>(*context_, s.offer, sctp);
        }
        webrtc::StunAddress mapped;
        if (from.ipv6()) {
            std::array<std::uint8_t, 16> ip{};
            std::copy_n(from.ip_bytes().begin(), 16, ip.begin());
            mapped = webrtc::StunAddress::v6(ip, from.port());
        } else {
            std::array<std::uint8_t, 4> ip{};
            std::copy_n(from.ip_bytes().begin(), 4, ip.begin());
            mapped = webrtc::StunAddress::v4(ip, from.port());
        }
        send_datagram(webrtc::build_binding_success(m.transaction_id, mapped, s.ice.pwd), from);
    }

    void bind(RtcSession& s, const Endpoint& from) {
        if (s.remote) {
            if (const auto r = by_remote_.find(s.remote->key()); r != by_remote_.end() && r->second == s.peer) by_remote_.erase(r);
        }
        // Another session bound to this address loses it (a page that came back).
        by_remote_[from.key()] = s.peer;
        s.remote = from;
    }

    void on_dtls(std::span<const std::uint8_t> d, const Endpoint& from, std::uint64_t& limited) {
        const auto it = by_remote_.find(from.key());
        if (it == by_remote_.end()) return;
        const auto found = sessions_.find(it->second);
        if (found == sessions_.end()) return;
        RtcSession& s = found->second;
        if (!s.channels || !s.remote || s.remote->key() != from.key()) return;
        if (d[0] == kDtlsHandshake && !handshake_limits_.allow(from.ip_key(), now_)) {
            ++limited;
            return;
        }
        s.last_received_ms = now_;
        s.channels->feed(d);
    }

    /// Advances one session; true when it is over.
    bool step(RtcSession& s, std::vector<net::Event>& events);
    std::map<net::PeerId, RtcSession>::iterator end(std::map<net::PeerId, RtcSession>::iterator it,
                                                    std::vector<net::Event>& events);
    void flush_session(RtcSession& s) {
        if (!s.channels || !s.remote) return;
        for (const auto& d : s.channels->take_outgoing()) send_datagram(d, *s.remote);
    }
    void send_datagram(std::span<const std::uint8_t> d, const Endpoint& to) {
        if (!socket_.send(d, to)) return;
        totals_.bytes_sent += d.size();
        ++totals_.packets_sent;
    }

    const RtcConfig config_;
    std::unique_ptr<webrtc::DtlsContext> context_;
    std::shared_ptr<detail::SignalState> signal_;
    detail::UdpSocket socket_;
    std::array<std::uint8_t, 2048> buffer_{};
    std::uint64_t now_ = 0;
    net::PeerId next_peer_;
    std::map<net::PeerId, RtcSession> sessions_;
    std::map<std::string, net::PeerId> by_ufrag_, by_remote_;
    detail::RateLimits stun_limits_, handshake_limits_;
    net::Totals totals_;
};

bool RtcTransport::step(RtcSession& s, std::vector<net::Event>& events) {
    if (!s.channels) return now_ > s.created_ms + config_.pending_timeout_ms;
    webrtc::DataChannelSession& c = *s.channels;
    c.handle_timeout();
    for (const std::uint16_t stream : c.take_opened()) {
        const webrtc::DataChannelOpen* open = c.channel(stream);
        if (open->label == "unreliable" && !s.streams[0]) s.streams[0] = stream;
        if (open->label == "reliable" && !s.streams[1]) s.streams[1] = stream;
    }
    if (!s.connected && s.streams[0] && s.streams[1]) {
        s.connected = true;
        signal_->settled(s.address, false);
        events.push_back({net::Event::Type::connected, s.peer, net::Channel::reliable, {}, 0});
    }
    for (webrtc::ChannelMessage& m : c.take_messages()) {
        const auto channel = m.stream == s.streams[0] ? net::Channel::unreliable : net::Channel::reliable;
        if (!s.connected || s.closing || (m.stream != s.streams[0] && m.stream != s.streams[1]) || m.data.empty()) continue;
        events.push_back({net::Event::Type::received, s.peer, channel, std::move(m.data), 0});
    }
    bool over = false;
    for (const std::uint16_t stream : c.take_closed()) over |= stream == s.streams[0] || stream == s.streams[1];
    const auto state = c.state();
    over |= state == webrtc::SessionState::kClosed || state == webrtc::SessionState::kFailed;
    if (state == webrtc::SessionState::kFailed) spdlog::debug("webrtc: session {} failed: {}", s.peer, c.error_detail());
    over |= !s.connected && now_ > s.created_ms + config_.pending_timeout_ms;
    over |= now_ > s.last_received_ms + config_.timeout_ms;
    if (s.closing && now_ >= s.closing_ms + kCloseGraceMs) {
        c.close();
        over = true;
    }
    flush_session(s);
    return over;
}

std::map<net::PeerId, RtcSession>::iterator RtcTransport::end(std::map<net::PeerId, RtcSession>::iterator it,
                                                              std::vector<net::Event>& events) {
    RtcSession& s = it->second;
    if (s.connected) events.push_back({net::Event::Type::disconnected, s.peer, net::Channel::reliable, {}, 0});
    else signal_->settled(s.address, true);
    signal_->ended();
    if (const auto u = by_ufrag_.find(s.ice.ufrag); u != by_ufrag_.end() && u->second == s.peer) by_ufrag_.erase(u);
    if (s.remote) {
        if (const auto r = by_remote_.find(s.remote->key()); r != by_remote_.end() && r->second == s.peer) by_remote_.erase(r);
    }
    return sessions_.erase(it);
}

}  // namespace

std::string validate(const RtcConfig& c) {
    if (c.max_sessions < 1 || c.max_pending < 1 || c.max_pending_per_address < 1) return "webrtc: caps must be at least 1";
    if (c.pending_timeout_ms < 1000 || c.timeout_ms < 1000) return "webrtc: timeouts must be at least 1000 ms";
    in6_addr ip{};
    if (!c.candidate_ip.empty() && inet_pton(AF_INET, c.candidate_ip.c_str(), &ip) != 1 &&
        inet_pton(AF_INET6, c.candidate_ip.c_str(), &ip) != 1) {
        return "--webrtc-address " + c.candidate_ip + ": not an IP address";
    }
    if (c.stun_per_s <= 0 || c.stun_burst < 1 || c.handshake_per_s <= 0 || c.handshake_burst < 1) {
        return "webrtc: rate limits must be positive";
    }
    return {};
}

std::unique_ptr<net::Transport> listen_rtc(const RtcConfig& config, std::shared_ptr<RtcSignal>& signal,
                                           std::string& error) {
    if (error = validate(config); !error.empty()) return nullptr;
    webrtc::DtlsSettings dtls;
    dtls.mtu_bytes = 1150;
    auto context = webrtc::DtlsContext::create(dtls, &error);
    if (!context) return nullptr;
    auto t = std::make_unique<RtcTransport>(config, std::move(context));
    if (!t->open(signal, error)) return nullptr;
    return t;
}

RtcStats rtc_stats(const net::Transport& transport) {
    const auto* t = dynamic_cast<const RtcTransport*>(&transport);
    return t != nullptr ? t->stats() : RtcStats{};
}

}  // namespace jetrace::rtc
