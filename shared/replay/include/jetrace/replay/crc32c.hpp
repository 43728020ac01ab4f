// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78, initial value and
// final xor 0xFFFFFFFF): the check value of every replay record. crc32c of
// the nine ASCII bytes "123456789" is 0xE3069283.
#pragma once

#include <cstdint>
#include <span>

namespace jetrace::replay {

/// Continues a CRC-32C: pass the previous result as `crc` (0 to start).
std::uint32_t crc32c(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

}  // namespace jetrace::replay
