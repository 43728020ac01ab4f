// One SCTP association on an AF_CONN socket: its options, connecting,
// packets in and out, messages, notifications and stream resets.
#include "sctp_stack.hpp"

#include <usrsctp.h>

#include <arpa/inet.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace jetrace::webrtc {

namespace {

// usrsctp 0.9.5.0 (Debian 12) cuts a large message into DATA chunks that
// fill the path MTU of an AF_CONN association without counting the 12-byte
// SCTP common header: its packets are then 12 bytes over. The MTU it is
// given is that much smaller, so no packet exceeds mtu_bytes.
constexpr std::uint32_t kCommonHeaderBytes = 12;

sockaddr_conn conn_address(std::uintptr_t id, std::uint16_t port) {
    sockaddr_conn a{};
    a.sconn_family = AF_CONN;
    a.sconn_port = htons(port);
    a.sconn_addr = reinterpret_cast<void*>(id);
    return a;
}

template <typename T>
bool set_option(struct socket* s, int level, int name, const T& value) {
    return usrsctp_setsockopt(s, level, name, &value, static_cast<socklen_t>(sizeof value)) == 0;
}

bool subscribe(struct socket* s, std::uint16_t type) {
    sctp_event event{};
    event.se_assoc_id = SCTP_ALL_ASSOC;
    event.se_on = 1;
    event.se_type = type;
    return set_option(s, IPPROTO_SCTP, SCTP_EVENT, event);
}

}  // namespace

SctpAssociation::SctpAssociation(const SctpSettings& settings) : settings_(settings) {
    id_ = detail::register_association(this, settings.globals);
    socket_ = usrsctp_socket(AF_CONN, SOCK_STREAM, IPPROTO_SCTP, &detail::SctpCallbacks::receive, nullptr, 0,
                             reinterpret_cast<void*>(id_));
    if (socket_ == nullptr) {
        fail("usrsctp_socket");
    } else if (configure()) {
        start();
    }
}

void SctpAssociation::start() {
    sockaddr_conn local = conn_address(id_, settings_.local_port);
    if (usrsctp_bind(socket_, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) {
        fail("usrsctp_bind");
        return;
    }
    // The remote end has the same AF_CONN address, the association's own, as in WebRTC.
    sockaddr_conn remote = conn_address(id_, settings_.remote_port);
    if (usrsctp_connect(socket_, reinterpret_cast<sockaddr*>(&remote), sizeof remote) != 0 && errno != EINPROGRESS)
        fail("usrsctp_connect");
}

SctpAssociation::~SctpAssociation() {
    if (socket_ != nullptr) usrsctp_close(socket_);  // SO_LINGER 0: an ABORT, dropped with the rest
    detail::unregister_association(id_);
}

bool SctpAssociation::configure() {
    struct socket* s = socket_;
    const linger abort_on_close{1, 0};
    sctp_assoc_value reset{};
    reset.assoc_id = SCTP_ALL_ASSOC;
    reset.assoc_value = SCTP_ENABLE_RESET_STREAM_REQ;
    sctp_initmsg init{};
    init.sinit_num_ostreams = settings_.streams;
    init.sinit_max_instreams = settings_.streams;
    sctp_paddrparams path{};
    path.spp_assoc_id = SCTP_FUTURE_ASSOC;
    path.spp_pathmtu = settings_.mtu_bytes - kCommonHeaderBytes;
    path.spp_flags = SPP_PMTUD_DISABLE;  // the MTU is the DTLS budget, not a path to probe
    const int on = 1;
    const bool ok = usrsctp_set_non_blocking(s, 1) == 0 && set_option(s, SOL_SOCKET, SO_LINGER, abort_on_close) &&
                    set_option(s, IPPROTO_SCTP, SCTP_ENABLE_STREAM_RESET, reset) &&
                    set_option(s, IPPROTO_SCTP, SCTP_INITMSG, init) && set_option(s, IPPROTO_SCTP, SCTP_NODELAY, on) &&
                    set_option(s, IPPROTO_SCTP, SCTP_RECVRCVINFO, on) &&
                    set_option(s, IPPROTO_SCTP, SCTP_PEER_ADDR_PARAMS, path) && subscribe(s, SCTP_ASSOC_CHANGE) &&
                    subscribe(s, SCTP_STREAM_RESET_EVENT);
    if (!ok) fail("usrsctp_setsockopt");
    return ok;
}

void SctpAssociation::fail(const std::string& what) {
    state_ = SctpState::kFailed;
    detail_ = what + ": " + std::strerror(errno);
}

void SctpAssociation::feed(std::span<const std::uint8_t> packet) {
    if (socket_ == nullptr || state_ == SctpState::kFailed || packet.empty()) return;
    usrsctp_conninput(reinterpret_cast<void*>(id_), packet.data(), packet.size(), 0);
}

std::vector<std::vector<std::uint8_t>> SctpAssociation::take_outgoing() { return std::exchange(outgoing_, {}); }
std::vector<SctpMessage> SctpAssociation::take_messages() { return std::exchange(messages_, {}); }
std::vector<std::uint16_t> SctpAssociation::take_reset_streams() { return std::exchange(reset_streams_, {}); }

void SctpAssociation::on_receive(std::span<const std::uint8_t> data, std::uint16_t stream, std::uint32_t ppid,
                                 bool unordered, bool end_of_record) {
    // usrsctp hands over a large message in pieces (partial delivery): one
    // message at a time, joined here up to max_message_bytes.
    if (partial_.data.empty() && !partial_too_large_) {
        partial_.stream = stream;
        partial_.ppid = ppid;
        partial_.unordered = unordered;
    }
    if (partial_.data.size() + data.size() > settings_.max_message_bytes) {
        partial_too_large_ = true;
        partial_.data.clear();
    } else if (!partial_too_large_) {
        partial_.data.insert(partial_.data.end(), data.begin(), data.end());
    }
    if (!end_of_record) return;
    if (!partial_too_large_) messages_.push_back(std::move(partial_));
    partial_ = SctpMessage{};
    partial_too_large_ = false;
}

void SctpAssociation::on_notification(std::span<const std::uint8_t> bytes) {
    decltype(sctp_notification::sn_header) header{};
    if (bytes.size() < sizeof header) return;
    std::memcpy(&header, bytes.data(), sizeof header);
    if (header.sn_type == SCTP_ASSOC_CHANGE && bytes.size() >= sizeof(sctp_assoc_change)) {
        sctp_assoc_change change{};
        std::memcpy(&change, bytes.data(), sizeof change);
        if (change.sac_state == SCTP_COMM_UP) {
            state_ = SctpState::kConnected;
        } else if (change.sac_state == SCTP_COMM_LOST || change.sac_state == SCTP_SHUTDOWN_COMP ||
                   change.sac_state == SCTP_CANT_STR_ASSOC) {
            state_ = SctpState::kClosed;
        }
    } else if (header.sn_type == SCTP_STREAM_RESET_EVENT && bytes.size() >= sizeof(sctp_stream_reset_event)) {
        sctp_stream_reset_event event{};
        std::memcpy(&event, bytes.data(), sizeof event);
        if ((event.strreset_flags & SCTP_STREAM_RESET_INCOMING_SSN) == 0) return;  // only the peer's resets
        const std::size_t count = (bytes.size() - sizeof event) / sizeof(std::uint16_t);
        for (std::size_t i = 0; i < count; ++i) {
            std::uint16_t stream = 0;
            std::memcpy(&stream, bytes.data() + sizeof event + i * sizeof stream, sizeof stream);
            reset_streams_.push_back(stream);
        }
    }
}

SctpSendResult SctpAssociation::send(std::uint16_t stream, std::uint32_t ppid, std::span<const std::uint8_t> data,
                                     const SctpSendOptions& options) {
    if (state_ != SctpState::kConnected) return SctpSendResult::kNotConnected;
    if (data.empty()) return SctpSendResult::kEmpty;
    if (data.size() > settings_.max_message_bytes) return SctpSendResult::kTooLarge;
    sctp_sendv_spa spa{};
    spa.sendv_flags = SCTP_SEND_SNDINFO_VALID;
    spa.sendv_sndinfo.snd_sid = stream;
    spa.sendv_sndinfo.snd_ppid = htonl(ppid);
    spa.sendv_sndinfo.snd_flags = SCTP_EOR | (options.unordered ? SCTP_UNORDERED : 0);
    if (options.max_retransmits || options.lifetime_ms) {
        spa.sendv_flags |= SCTP_SEND_PRINFO_VALID;
        spa.sendv_prinfo.pr_policy = options.max_retransmits ? SCTP_PR_SCTP_RTX : SCTP_PR_SCTP_TTL;
        spa.sendv_prinfo.pr_value = options.max_retransmits ? *options.max_retransmits : *options.lifetime_ms;
    }
    const ssize_t n = usrsctp_sendv(socket_, data.data(), data.size(), nullptr, 0, &spa,
                                    static_cast<socklen_t>(sizeof spa), SCTP_SENDV_SPA, 0);
    if (n == static_cast<ssize_t>(data.size())) return SctpSendResult::kSent;
    if (n < 0 && (errno == EWOULDBLOCK || errno == EAGAIN)) return SctpSendResult::kWouldBlock;
    return SctpSendResult::kFailed;
}

bool SctpAssociation::reset_stream(std::uint16_t stream) {
    if (state_ != SctpState::kConnected) return false;
    alignas(sctp_reset_streams) std::uint8_t buf[sizeof(sctp_reset_streams) + sizeof(std::uint16_t)] = {};
    auto* reset = reinterpret_cast<sctp_reset_streams*>(buf);
    reset->srs_assoc_id = SCTP_ALL_ASSOC;
    reset->srs_flags = SCTP_STREAM_RESET_OUTGOING;
    reset->srs_number_streams = 1;
    std::memcpy(buf + sizeof(sctp_reset_streams), &stream, sizeof stream);
    return usrsctp_setsockopt(socket_, IPPROTO_SCTP, SCTP_RESET_STREAMS, buf, sizeof buf) == 0;
}

}  // namespace jetrace::webrtc
