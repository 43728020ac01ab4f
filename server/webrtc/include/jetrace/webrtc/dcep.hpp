// The Data Channel Establishment Protocol (RFC 8832): the browser opens a
// channel with DATA_CHANNEL_OPEN on an SCTP stream (PPID 50); the other end
// answers DATA_CHANNEL_ACK on the same stream. Also the SCTP payload
// protocol identifiers of data channel messages (RFC 8831 section 8).
// parse_dcep_open reads untrusted bytes; fuzzed by fuzz/fuzz_dcep.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace jetrace::webrtc {

// SCTP payload protocol identifiers (PPID).
inline constexpr std::uint32_t kPpidDcep = 50;
inline constexpr std::uint32_t kPpidString = 51;
inline constexpr std::uint32_t kPpidBinary = 53;
inline constexpr std::uint32_t kPpidStringEmpty = 56;
inline constexpr std::uint32_t kPpidBinaryEmpty = 57;

// DCEP message types.
inline constexpr std::uint8_t kDcepAck = 0x02;
inline constexpr std::uint8_t kDcepOpen = 0x03;

// DATA_CHANNEL_OPEN channel types: the high bit is "unordered".
inline constexpr std::uint8_t kChannelReliable = 0x00;
inline constexpr std::uint8_t kChannelReliableUnordered = 0x80;
inline constexpr std::uint8_t kChannelPartialReliableRexmit = 0x01;
inline constexpr std::uint8_t kChannelPartialReliableRexmitUnordered = 0x81;
inline constexpr std::uint8_t kChannelPartialReliableTimed = 0x02;
inline constexpr std::uint8_t kChannelPartialReliableTimedUnordered = 0x82;

/// Type, channel type, priority, reliability, label and protocol lengths (unit: bytes).
inline constexpr std::size_t kDcepOpenHeaderBytes = 12;

struct DataChannelOpen {
    std::uint8_t channel_type = kChannelReliable;
    std::uint16_t priority = 0;
    /// Retransmissions (rexmit) or lifetime (unit: ms, timed); 0 when reliable.
    std::uint32_t reliability = 0;
    std::string label;
    std::string protocol;

    bool unordered() const { return (channel_type & 0x80) != 0; }
    /// Partially reliable: a limit on retransmissions or on lifetime.
    bool partial() const { return (channel_type & 0x7f) != 0; }
    bool operator==(const DataChannelOpen&) const = default;
};

enum class DcepError : std::uint8_t {
    kNone = 0,
    kEmpty,
    kNotOpen,         ///< the first byte is not DATA_CHANNEL_OPEN (0x03)
    kTooShort,        ///< fewer than the 12 header bytes
    kBadChannelType,  ///< not one of the six channel types
    kLengthMismatch,  ///< label and protocol lengths are not the rest of the message
};

std::string_view to_string(DcepError error);

/// Reads a DATA_CHANNEL_OPEN (a PPID 50 message). The label and protocol
/// are bytes as sent (RFC 8832 says UTF-8; not checked here).
DcepError parse_dcep_open(std::span<const std::uint8_t> message, DataChannelOpen& out);

/// True if `message` is exactly a DATA_CHANNEL_ACK.
bool is_dcep_ack(std::span<const std::uint8_t> message);

/// The DATA_CHANNEL_OPEN of `open` (label and protocol up to 65535 bytes: asserted).
std::vector<std::uint8_t> build_dcep_open(const DataChannelOpen& open);

/// DATA_CHANNEL_ACK: the single byte 0x02.
std::vector<std::uint8_t> build_dcep_ack();

}  // namespace jetrace::webrtc
