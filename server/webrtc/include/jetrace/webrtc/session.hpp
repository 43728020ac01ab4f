// One browser's data channels after ICE: DTLS (server role, the offer's
// fingerprint), SCTP over it, and DCEP: the browser's DATA_CHANNEL_OPENs are
// acknowledged and remembered per stream, messages arrive with their
// channel, and send() uses each channel's own ordering and reliability
// (RFC 8831). No sockets and no STUN: the caller feeds the datagrams that
// is_dtls() picks from the browser's address after its ICE check, and sends
// what take_outgoing() returns. SCTP timers are process-wide:
// SctpAssociation::advance_timers.
#pragma once

#include "jetrace/webrtc/dcep.hpp"
#include "jetrace/webrtc/dtls.hpp"
#include "jetrace/webrtc/sctp.hpp"
#include "jetrace/webrtc/sdp.hpp"

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace jetrace::webrtc {

enum class SessionState : std::uint8_t {
    kConnecting,  ///< DTLS or SCTP handshake under way
    kOpen,        ///< SCTP associated: channels can open
    kClosed,      ///< DTLS close_notify or SCTP shutdown/abort
    kFailed,      ///< DTLS refused (fingerprint, handshake, timeout): error_detail()
};

/// A message on an open channel.
struct ChannelMessage {
    std::uint16_t stream = 0;
    bool binary = true;  ///< PPID 53/57, else a string (51/56)
    std::vector<std::uint8_t> data;
};

class DataChannelSession {
public:
    /// `context` (the server's certificate) must outlive the session.
    DataChannelSession(DtlsContext& context, const SdpOffer& offer, const SctpSettings& sctp = {});

    /// One datagram from the browser (untrusted): DTLS records.
    void feed(std::span<const std::uint8_t> datagram);
    /// DTLS retransmission timers (call from the loop; next_timeout() says when).
    void handle_timeout();
    std::optional<std::chrono::milliseconds> next_timeout() const { return dtls_.next_timeout(); }
    /// The datagrams to send to the browser, SCTP's pending packets included.
    std::vector<std::vector<std::uint8_t>> take_outgoing();

    /// Messages received on open channels since the last call.
    std::vector<ChannelMessage> take_messages();
    /// Streams whose channel the browser opened, or closed, since the last call.
    std::vector<std::uint16_t> take_opened();
    std::vector<std::uint16_t> take_closed();
    /// The channel open on `stream`, if any.
    const DataChannelOpen* channel(std::uint16_t stream) const;
    /// The stream of the open channel with this label, if any.
    std::optional<std::uint16_t> find_channel(std::string_view label) const;

    /// A message on an open channel, with the channel's reliability: binary
    /// (PPID 53), or a string (51) when `binary` is false.
    SctpSendResult send(std::uint16_t stream, std::span<const std::uint8_t> data, bool binary = true);

    /// Sends DTLS close_notify (in take_outgoing()); the session is then closed.
    void close() { dtls_.close(); }

    SessionState state() const;
    /// Why the session failed (DTLS's reason, else usrsctp's), "" otherwise.
    std::string error_detail() const;

private:
    void on_sctp_message(SctpMessage& m);
    void pump_sctp();

    DtlsEndpoint dtls_;
    SctpAssociation sctp_;
    std::map<std::uint16_t, DataChannelOpen> channels_;
    std::vector<ChannelMessage> messages_;
    std::vector<std::uint16_t> opened_;
    std::vector<std::uint16_t> closed_;
};

}  // namespace jetrace::webrtc
