// Big-endian reads and writes of the wire formats in this folder (STUN,
// DCEP). Readers take an offset the caller has checked against the size.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace jetrace::webrtc::detail {

inline std::uint16_t load_u16(std::span<const std::uint8_t> b, std::size_t at) {
    return static_cast<std::uint16_t>((b[at] << 8) | b[at + 1]);
}

inline std::uint32_t load_u32(std::span<const std::uint8_t> b, std::size_t at) {
    return (static_cast<std::uint32_t>(load_u16(b, at)) << 16) | load_u16(b, at + 2);
}

inline std::uint64_t load_u64(std::span<const std::uint8_t> b, std::size_t at) {
    return (static_cast<std::uint64_t>(load_u32(b, at)) << 32) | load_u32(b, at + 4);
}

inline void append_u16(std::vector<std::uint8_t>& out, std::uint16_t v) {
    out.push_back(static_cast<std::uint8_t>(v >> 8));
    out.push_back(static_cast<std::uint8_t>(v));
}

inline void append_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    append_u16(out, static_cast<std::uint16_t>(v >> 16));
    append_u16(out, static_cast<std::uint16_t>(v));
}

inline void append_u64(std::vector<std::uint8_t>& out, std::uint64_t v) {
    append_u32(out, static_cast<std::uint32_t>(v >> 32));
    append_u32(out, static_cast<std::uint32_t>(v));
}

inline void store_u16(std::vector<std::uint8_t>& out, std::size_t at, std::uint16_t v) {
    out[at] = static_cast<std::uint8_t>(v >> 8);
    out[at + 1] = static_cast<std::uint8_t>(v);
}

}  // namespace jetrace::webrtc::detail
