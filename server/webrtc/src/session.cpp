// A browser's data channels: DTLS records carry SCTP packets, DCEP opens
// channels, messages go out with each channel's reliability.
#include "jetrace/webrtc/session.hpp"

#include <utility>

namespace jetrace::webrtc {

namespace {

// The browser's SCTP port is the offer's a=sctp-port.
SctpSettings with_remote_port(SctpSettings s, const SdpOffer& offer) {
    s.remote_port = offer.sctp_port;
    return s;
}

// RFC 8831 section 6.6: an empty message is one zero byte with PPID 56 or 57.
bool empty_ppid(std::uint32_t ppid) { return ppid == kPpidStringEmpty || ppid == kPpidBinaryEmpty; }

}  // namespace

DataChannelSession::DataChannelSession(DtlsContext& context, const SdpOffer& offer, const SctpSettings& sctp)
    : dtls_(context, DtlsRole::kServer, offer.fingerprint), sctp_(with_remote_port(sctp, offer)) {}

void DataChannelSession::feed(std::span<const std::uint8_t> datagram) {
    dtls_.feed(datagram);
    pump_sctp();
}

void DataChannelSession::handle_timeout() { dtls_.handle_timeout(); }

void DataChannelSession::pump_sctp() {
    for (const auto& packet : dtls_.take_received()) sctp_.feed(packet);
    for (SctpMessage& m : sctp_.take_messages()) on_sctp_message(m);
    // The browser closed a channel: its stream is reset both ways (RFC 8831 section 6.7).
    for (const std::uint16_t stream : sctp_.take_reset_streams()) {
        if (channels_.erase(stream) > 0) closed_.push_back(stream);
        sctp_.reset_stream(stream);
    }
}

void DataChannelSession::on_sctp_message(SctpMessage& m) {
    if (m.ppid == kPpidDcep) {
        DataChannelOpen open;
        if (parse_dcep_open(m.data, open) != DcepError::kNone || channels_.count(m.stream) > 0) return;
        channels_.emplace(m.stream, std::move(open));
        opened_.push_back(m.stream);
        sctp_.send(m.stream, kPpidDcep, build_dcep_ack());  // reliable and ordered, as DCEP must be
        return;
    }
    const bool known = m.ppid == kPpidBinary || m.ppid == kPpidString || empty_ppid(m.ppid);
    if (!known || channels_.count(m.stream) == 0) return;
    if (empty_ppid(m.ppid)) m.data.clear();
    messages_.push_back({m.stream, m.ppid == kPpidBinary || m.ppid == kPpidBinaryEmpty, std::move(m.data)});
}

std::vector<std::vector<std::uint8_t>> DataChannelSession::take_outgoing() {
    if (dtls_.handshake_done()) {
        for (const auto& packet : sctp_.take_outgoing()) dtls_.send(packet);
    }
    return dtls_.take_outgoing();
}

std::vector<ChannelMessage> DataChannelSession::take_messages() { return std::exchange(messages_, {}); }
std::vector<std::uint16_t> DataChannelSession::take_opened() { return std::exchange(opened_, {}); }
std::vector<std::uint16_t> DataChannelSession::take_closed() { return std::exchange(closed_, {}); }

const DataChannelOpen* DataChannelSession::channel(std::uint16_t stream) const {
    const auto it = channels_.find(stream);
    return it == channels_.end() ? nullptr : &it->second;
}

std::optional<std::uint16_t> DataChannelSession::find_channel(std::string_view label) const {
    for (const auto& [stream, open] : channels_)
        if (open.label == label) return stream;
    return std::nullopt;
}

SctpSendResult DataChannelSession::send(std::uint16_t stream, std::span<const std::uint8_t> data, bool binary) {
    const DataChannelOpen* open = channel(stream);
    if (open == nullptr) return SctpSendResult::kNotConnected;
    SctpSendOptions options;
    options.unordered = open->unordered();
    const std::uint8_t reliability = open->channel_type & 0x7f;
    if (reliability == kChannelPartialReliableRexmit) options.max_retransmits = open->reliability;
    if (reliability == kChannelPartialReliableTimed) options.lifetime_ms = open->reliability;
    if (data.empty()) {
        const std::uint8_t zero = 0;
        return sctp_.send(stream, binary ? kPpidBinaryEmpty : kPpidStringEmpty, {&zero, 1}, options);
    }
    return sctp_.send(stream, binary ? kPpidBinary : kPpidString, data, options);
}

std::string DataChannelSession::error_detail() const {
    return dtls_.error_detail().empty() ? sctp_.error_detail() : dtls_.error_detail();
}

SessionState DataChannelSession::state() const {
    if (dtls_.state() == DtlsState::kFailed || sctp_.state() == SctpState::kFailed) return SessionState::kFailed;
    if (dtls_.state() == DtlsState::kClosed || sctp_.state() == SctpState::kClosed) return SessionState::kClosed;
    return sctp_.state() == SctpState::kConnected ? SessionState::kOpen : SessionState::kConnecting;
}

}  // namespace jetrace::webrtc
