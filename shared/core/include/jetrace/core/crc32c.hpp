// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78, initial value and
// final xor 0xFFFFFFFF): the check value of every replay record and of the
// compiled track format (.jtrack). crc32c of the nine ASCII bytes
// "123456789" is 0xE3069283.
#pragma once

#include <cstdint>
#include <span>

namespace jetrace {

/// Continues a CRC-32C: pass the previous result as `crc` (0 to start).
/// On x86-64 processors with SSE4.2 (checked once, at run time) by the
/// processor's CRC-32C instruction, about four times the speed of the
/// tables; elsewhere by crc32c_tables. The same result either way.
std::uint32_t crc32c(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

/// crc32c by tables alone (slicing by 8), on every processor.
std::uint32_t crc32c_tables(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

}  // namespace jetrace
