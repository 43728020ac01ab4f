// SCTP over DTLS (RFC 8261) with Debian's usrsctp, as WebRTC data channels
// use it (RFC 8831): each association is an AF_CONN socket whose packets go
// to and from the caller (who carries them in DTLS records), initialised
// with usrsctp_init_nothreads: no timer thread and no receive thread; its
// timers are advanced by the caller's loop (SctpAssociation::advance_timers),
// and every callback runs inside the caller's calls. (Debian 12's usrsctp
// 0.9.5.0 still starts its "SCTP iterator" thread, which sleeps until an
// iteration over endpoints bound to all addresses or a send-to-all is asked
// for; these associations are bound to one AF_CONN address each, with ASCONF
// off, and never ask.)
//
// Time: the retransmission timer runs on the caller's clock, but when it
// fires usrsctp resends a chunk only if it has been out longer than the
// smoothed RTT by the real clock (sctp_mark_all_for_resend).
//
// usrsctp is a process-wide singleton: the first association initialises
// it (with the SctpGlobals in force then) and it stays for the process.
// Every association is told apart by its own AF_CONN address. Not thread
// safe: one thread (the server loop) makes every call.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

struct socket;

namespace jetrace::webrtc {

namespace detail {
struct SctpCallbacks;
}  // namespace detail

/// usrsctp's process-wide tunables, applied when the first association
/// initialises usrsctp (later values are ignored).
struct SctpGlobals {
    std::uint32_t rto_initial_ms = 1000;
    std::uint32_t rto_min_ms = 200;
    std::uint32_t rto_max_ms = 10000;
    std::uint32_t delayed_sack_ms = 20;
    std::uint32_t heartbeat_interval_ms = 10000;
};

struct SctpSettings {
    /// Both ends' SCTP port: the SDP's a=sctp-port (5000 in browsers).
    std::uint16_t local_port = 5000;
    std::uint16_t remote_port = 5000;
    /// The largest SCTP packet written (unit: bytes): the DTLS datagram
    /// budget (~1150) less the DTLS record overhead (AES-GCM: 37 bytes).
    std::uint32_t mtu_bytes = 1100;
    /// Streams offered and accepted each way (a data channel uses one each way).
    std::uint16_t streams = 1024;
    /// The largest message kept while its pieces arrive (unit: bytes);
    /// larger ones are dropped.
    std::size_t max_message_bytes = 64 * 1024;
    SctpGlobals globals;
};

enum class SctpState : std::uint8_t { kConnecting, kConnected, kClosed, kFailed };

/// One received message on a stream.
struct SctpMessage {
    std::uint16_t stream = 0;
    std::uint32_t ppid = 0;  ///< kPpidDcep, kPpidBinary... (dcep.hpp)
    bool unordered = false;
    std::vector<std::uint8_t> data;
};

/// How a message is sent. Reliable and ordered by default; WebRTC's
/// unreliable channel is {.unordered = true, .max_retransmits = 0}.
struct SctpSendOptions {
    bool unordered = false;
    /// PR-SCTP: retransmitted at most this many times, then abandoned.
    std::optional<std::uint32_t> max_retransmits;
    /// PR-SCTP: abandoned this long after it was sent (unit: ms); ignored
    /// with max_retransmits.
    std::optional<std::uint32_t> lifetime_ms;
};

enum class SctpSendResult : std::uint8_t {
    kSent = 0,
    kNotConnected,
    kEmpty,      ///< WebRTC sends empty messages as one byte with PPID 56/57
    kTooLarge,   ///< more than max_message_bytes
    kWouldBlock, ///< the send buffer is full
    kFailed,
};

class SctpAssociation {
public:
    /// Creates the socket and starts connecting (INIT goes to take_outgoing();
    /// both ends connect, as in WebRTC). state() is kFailed if usrsctp refused.
    explicit SctpAssociation(const SctpSettings& settings);
    ~SctpAssociation();
    SctpAssociation(const SctpAssociation&) = delete;
    SctpAssociation& operator=(const SctpAssociation&) = delete;

    /// One SCTP packet from the peer (a DTLS record's plaintext; untrusted).
    void feed(std::span<const std::uint8_t> packet);
    /// The SCTP packets to send to the peer (each in one DTLS record).
    std::vector<std::vector<std::uint8_t>> take_outgoing();
    /// Messages received since the last call.
    std::vector<SctpMessage> take_messages();
    /// Streams the peer reset (a data channel closed) since the last call;
    /// RFC 8831 section 6.7: answer with reset_stream() on each.
    std::vector<std::uint16_t> take_reset_streams();

    SctpSendResult send(std::uint16_t stream, std::uint32_t ppid, std::span<const std::uint8_t> data,
                        const SctpSendOptions& options = {});
    /// Resets our outgoing side of `stream` (closing a data channel).
    bool reset_stream(std::uint16_t stream);

    SctpState state() const { return state_; }
    const std::string& error_detail() const { return detail_; }

    /// Advances usrsctp's timers (retransmissions, SACKs, heartbeats) of
    /// every association by `elapsed_ms` of the caller's clock.
    static void advance_timers(std::uint32_t elapsed_ms);

private:
    friend struct detail::SctpCallbacks;  // usrsctp's output and receive callbacks
    void on_receive(std::span<const std::uint8_t> data, std::uint16_t stream, std::uint32_t ppid, bool unordered,
                    bool end_of_record);
    void on_notification(std::span<const std::uint8_t> bytes);
    bool configure();
    void start();
    void fail(const std::string& what);

    SctpSettings settings_;
    std::uintptr_t id_ = 0;  // the AF_CONN address usrsctp knows this association by
    struct socket* socket_ = nullptr;
    SctpState state_ = SctpState::kConnecting;
    std::string detail_;
    std::vector<std::vector<std::uint8_t>> outgoing_;
    std::vector<SctpMessage> messages_;
    std::vector<std::uint16_t> reset_streams_;
    SctpMessage partial_;  // a message whose pieces are still arriving
    bool partial_too_large_ = false;
};

}  // namespace jetrace::webrtc
