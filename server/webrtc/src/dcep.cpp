// DATA_CHANNEL_OPEN and DATA_CHANNEL_ACK (RFC 8832 section 5).
#include "jetrace/webrtc/dcep.hpp"

#include "byte_io.hpp"

#include <cassert>

namespace jetrace::webrtc {

namespace {

bool known_channel_type(std::uint8_t t) {
    switch (t) {
        case kChannelReliable:
        case kChannelReliableUnordered:
        case kChannelPartialReliableRexmit:
        case kChannelPartialReliableRexmitUnordered:
        case kChannelPartialReliableTimed:
        case kChannelPartialReliableTimedUnordered:
            return true;
        default:
            return false;
    }
}

}  // namespace

DcepError parse_dcep_open(std::span<const std::uint8_t> m, DataChannelOpen& out) {
    out = DataChannelOpen{};
    if (m.empty()) return DcepError::kEmpty;
    if (m[0] != kDcepOpen) return DcepError::kNotOpen;
    if (m.size() < kDcepOpenHeaderBytes) return DcepError::kTooShort;
    if (!known_channel_type(m[1])) return DcepError::kBadChannelType;
    const std::size_t label_bytes = detail::load_u16(m, 8);
    const std::size_t protocol_bytes = detail::load_u16(m, 10);
    if (m.size() - kDcepOpenHeaderBytes != label_bytes + protocol_bytes) return DcepError::kLengthMismatch;
    out.channel_type = m[1];
    out.priority = detail::load_u16(m, 2);
    out.reliability = detail::load_u32(m, 4);
    const auto label = m.subspan(kDcepOpenHeaderBytes, label_bytes);
    const auto protocol = m.subspan(kDcepOpenHeaderBytes + label_bytes, protocol_bytes);
    out.label.assign(label.begin(), label.end());
    out.protocol.assign(protocol.begin(), protocol.end());
    return DcepError::kNone;
}

bool is_dcep_ack(std::span<const std::uint8_t> m) { return m.size() == 1 && m[0] == kDcepAck; }

std::vector<std::uint8_t> build_dcep_open(const DataChannelOpen& open) {
    assert(open.label.size() <= 0xFFFF && open.protocol.size() <= 0xFFFF);
    std::vector<std::uint8_t> m;
    m.reserve(kDcepOpenHeaderBytes + open.label.size() + open.protocol.size());
    m.push_back(kDcepOpen);
    m.push_back(open.channel_type);
    detail::append_u16(m, open.priority);
    detail::append_u32(m, open.reliability);
    detail::append_u16(m, static_cast<std::uint16_t>(open.label.size()));
    detail::append_u16(m, static_cast<std::uint16_t>(open.protocol.size()));
    m.insert(m.end(), open.label.begin(), open.label.end());
    m.insert(m.end(), open.protocol.begin(), open.protocol.end());
    return m;
}

std::vector<std::uint8_t> build_dcep_ack() { return {kDcepAck}; }

std::string_view to_string(DcepError error) {
    switch (error) {
        case DcepError::kNone: return "ok";
        case DcepError::kEmpty: return "empty message";
        case DcepError::kNotOpen: return "not DATA_CHANNEL_OPEN";
        case DcepError::kTooShort: return "shorter than the header";
        case DcepError::kBadChannelType: return "unknown channel type";
        case DcepError::kLengthMismatch: return "label and protocol lengths do not match the message";
    }
    return "unknown DCEP error";
}

}  // namespace jetrace::webrtc
