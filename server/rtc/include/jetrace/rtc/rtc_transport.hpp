// The server's WebRTC data-channel transport (issue 33; docs/PROTOCOL.md,
// "Transport: WebRTC data channel"): browsers race over an unordered,
// unreliable data channel ("unreliable", net::Channel::unreliable) and an
// ordered, reliable one ("reliable", net::Channel::reliable), built from
// jetrace::webrtc's blocks.
//
// One non-blocking UDP socket serves every browser (ICE-lite: the server
// answers STUN checks and gathers no candidates). It is read and written
// only inside service(), on the caller's thread and clock; usrsctp's timers
// advance by the caller's clock too. The only other thread is the web
// port's I/O thread, which hands offers in through signal() (thread safe):
// it answers with the server's SDP at once and queues the session, which
// service() takes up. A STUN check naming a queued session's credentials,
// with valid integrity, binds the sender's address to it; DTLS from that
// address then goes to its DataChannelSession.
#pragma once

#include "jetrace/net/transport.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace jetrace::rtc {

struct RtcConfig {
    /// Address the UDP socket binds ("127.0.0.1": loopback only).
    std::string bind = "127.0.0.1";
    /// UDP port; 0 lets the system choose (see local_port()).
    std::uint16_t port = 0;
    /// The host candidate's IP in answers; "": the address the page's
    /// POST /rtc reached (the web port's local address).
    std::string candidate_ip;
    /// The host candidate's port in answers; 0: the bound port. (Tests set
    /// a port nothing listens on: the page's ICE then fails as behind a
    /// firewall that drops UDP.)
    std::uint16_t candidate_port = 0;
    /// Sessions (pending and connected) at once (unit: sessions).
    std::size_t max_sessions = 256;
    /// Offers answered whose channels have not opened yet: overall and per
    /// IP address of the POST (unit: sessions). Beyond them: HTTP 503.
    std::size_t max_pending = 64;
    std::size_t max_pending_per_address = 4;
    /// A pending session whose channels are not open after this is dropped (unit: ms).
    std::uint32_t pending_timeout_ms = 10000;
    /// A connected session that receives no datagram this long is dropped (unit: ms).
    std::uint32_t timeout_ms = 10000;
    /// Token buckets per remote IP: STUN requests, and DTLS handshake
    /// datagrams (ClientHellos, their retries and later flights) (unit: per
    /// second, and the burst).
    double stun_per_s = 50, stun_burst = 100;
    double handshake_per_s = 20, handshake_burst = 40;
    /// The lowest peer id handed out.
    net::PeerId peer_base = 0x60000000u;
};

/// Validates a config: "" or what is wrong.
std::string validate(const RtcConfig& config);

/// The lowest peer id of a data-channel session (below: ENet, WebSocket).
inline constexpr net::PeerId kRtcPeerBase = 0x60000000u;

/// The largest message sent on the unreliable channel (unit: bytes): one
/// SCTP DATA chunk in one packet of SctpSettings::mtu_bytes (1,100 less the
/// 12-byte common header and the 16-byte DATA chunk header), so that a
/// snapshot is never split into SCTP fragments. A larger one (a keyframe
/// snapshot of more than about 20 cars) goes whole on the reliable channel,
/// counted in RtcStats::unreliable_sent_reliably.
inline constexpr std::size_t kMaxUnreliableBytes = 1072;
/// The largest message on the reliable channel (unit: bytes): SCTP splits
/// it into packets of at most 1,100 bytes (TrackChunk: 6 KiB). Larger ones
/// (none: the protocol's messages are at most 8 KiB): send() false.
inline constexpr std::size_t kMaxReliableBytes = 16 * 1024;

/// What POST /rtc answers.
struct RtcReply {
    int status = 200;  ///< 200 (the answer), 400 (a bad offer), 503 (too many handshakes)
    std::string content_type = "application/sdp";
    std::string body;
};

/// The thread-safe signalling side of a transport made by listen_rtc; it
/// stays valid after the transport is gone (then it answers 503).
class RtcSignal {
public:
    virtual ~RtcSignal() = default;
    /// An offer posted from `address` (the HTTP client's IP) to the web
    /// port's `local_ip`; the reply to send back.
    virtual RtcReply offer(std::string_view sdp, const std::string& address, const std::string& local_ip) = 0;
};

/// Counters of a transport made by listen_rtc.
struct RtcStats {
    std::uint64_t offers_answered = 0;
    std::uint64_t offers_refused_bad = 0;   ///< 400
    std::uint64_t offers_refused_busy = 0;  ///< 503
    std::uint64_t pending_expired = 0;      ///< answered, no channels within pending_timeout_ms
    std::uint64_t rate_limited = 0;         ///< STUN or DTLS handshake datagrams over a bucket
    std::uint64_t unreliable_sent_reliably = 0;  ///< unreliable messages over kMaxUnreliableBytes
    std::uint64_t sessions_open = 0;
};

/// A bound UDP socket and its signalling: nullptr and `error` if it cannot bind.
std::unique_ptr<net::Transport> listen_rtc(const RtcConfig& config, std::shared_ptr<RtcSignal>& signal,
                                           std::string& error);

/// Counters of a transport made by listen_rtc (zeros for any other).
RtcStats rtc_stats(const net::Transport& transport);

}  // namespace jetrace::rtc
