#include "signal_state.hpp"

#include <openssl/rand.h>
#include <spdlog/spdlog.h>

#include <cstring>

namespace jetrace::rtc::detail {

namespace {

void random_bytes(std::span<std::uint8_t> out) {
    if (RAND_bytes(out.data(), static_cast<int>(out.size())) != 1) std::memset(out.data(), 0x5a, out.size());
}

}  // namespace

SignalState::SignalState(RtcConfig config, const webrtc::Sha256Fingerprint& fingerprint, std::uint16_t port)
    : config_(std::move(config)), fingerprint_(fingerprint), port_(port) {}

RtcReply SignalState::refuse(int status, std::string reason) {
    RtcReply r;
    r.status = status;
    r.content_type = "text/plain; charset=utf-8";
    r.body = std::move(reason) + "\n";
    return r;
}

RtcReply SignalState::offer(std::string_view sdp, const std::string& address, const std::string& local_ip) {
    webrtc::SdpOffer parsed;
    std::size_t line = 0;
    if (const webrtc::SdpError e = webrtc::parse_offer(sdp, parsed, &line); e != webrtc::SdpError::kNone) {
        std::lock_guard lock(mutex_);
        ++stats_.offers_refused_bad;
        std::string why = "bad offer: " + std::string(webrtc::to_string(e));
        if (line > 0) why += " (line " + std::to_string(line) + ")";
        return refuse(400, why);
    }
    webrtc::AnswerSettings s;
    s.ice = webrtc::make_ice_credentials(random_bytes);
    s.fingerprint = fingerprint_;
    s.candidate_ip = config_.candidate_ip.empty() ? local_ip : config_.candidate_ip;
    // A dual-stack web port sees IPv4 pages as ::ffff:a.b.c.d: answer with a.b.c.d.
    if (s.candidate_ip.rfind("::ffff:", 0) == 0 && s.candidate_ip.find('.') != std::string::npos) {
        s.candidate_ip.erase(0, 7);
    }
    s.candidate_port = config_.candidate_port != 0 ? config_.candidate_port : port_;
    s.max_message_size = static_cast<std::uint32_t>(kMaxReliableBytes);
    std::uint8_t id[8];
    random_bytes(id);
    std::uint64_t session_id = 0;
    for (const std::uint8_t b : id) session_id = session_id << 8 | b;
    s.session_id = (session_id >> 2) | 1;  // below 2^63, not 0
    std::lock_guard lock(mutex_);
    std::size_t& mine = pending_by_address_[address];
    const char* busy = closed_                                     ? "the server is stopping"
                       : sessions_ >= config_.max_sessions         ? "too many data-channel sessions are open"
                       : pending_ >= config_.max_pending           ? "too many data-channel handshakes are under way"
                       : mine >= config_.max_pending_per_address ? "too many data-channel handshakes from your address"
                                                                   : nullptr;
    if (busy != nullptr) {
        if (mine == 0) pending_by_address_.erase(address);
        ++stats_.offers_refused_busy;
        return refuse(503, busy);
    }
    ++mine;
    ++pending_;
    ++sessions_;
    ++stats_.offers_answered;
    RtcReply r;
    r.body = webrtc::write_answer(parsed, s);
    inbox_.push_back({address, std::move(s.ice), std::move(parsed)});
    return r;
}

std::vector<PendingOffer> SignalState::take_inbox() {
    std::lock_guard lock(mutex_);
    return std::exchange(inbox_, {});
}

void SignalState::settled(const std::string& address, bool expired) {
    std::lock_guard lock(mutex_);
    if (pending_ > 0) --pending_;
    if (const auto it = pending_by_address_.find(address); it != pending_by_address_.end() && --it->second == 0) {
        pending_by_address_.erase(it);
    }
    if (expired) ++stats_.pending_expired;
}

void SignalState::ended() {
    std::lock_guard lock(mutex_);
    if (sessions_ > 0) --sessions_;
}

void SignalState::close() {
    std::lock_guard lock(mutex_);
    closed_ = true;
}

void SignalState::count_rate_limited(std::uint64_t n) {
    std::lock_guard lock(mutex_);
    stats_.rate_limited += n;
}

void SignalState::count_sent_reliably() {
    std::lock_guard lock(mutex_);
    ++stats_.unreliable_sent_reliably;
}

RtcStats SignalState::stats() const {
    std::lock_guard lock(mutex_);
    RtcStats s = stats_;
    s.sessions_open = sessions_;
    return s;
}

}  // namespace jetrace::rtc::detail
