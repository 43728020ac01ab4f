// A WorldState as bytes: every field in a fixed order, little-endian, raw
// bits for doubles. Used by replays (the initial state) and for saving.
// Reading checks everything: the bytes may come from a file.
#pragma once

#include "jetrace/core/world.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace jetrace {

/// Appends the state to `out`.
void write_state(const WorldState& state, std::vector<std::uint8_t>& out);

/// Reads a state written by write_state from the front of `in`, advancing
/// `offset`. False with a reason if truncated or out of range.
bool read_state(std::span<const std::uint8_t> in, std::size_t& offset, WorldState& out, std::string& error);

/// Largest slot count read_state accepts.
inline constexpr std::uint32_t kMaxStateSlots = 1024;

/// Little-endian helpers shared by the binary formats.
void put_u8(std::vector<std::uint8_t>& out, std::uint8_t v);
void put_u16(std::vector<std::uint8_t>& out, std::uint16_t v);
void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v);
void put_u64(std::vector<std::uint8_t>& out, std::uint64_t v);
void put_f64(std::vector<std::uint8_t>& out, double v);
bool get_u8(std::span<const std::uint8_t> in, std::size_t& off, std::uint8_t& v);
bool get_u16(std::span<const std::uint8_t> in, std::size_t& off, std::uint16_t& v);
bool get_u32(std::span<const std::uint8_t> in, std::size_t& off, std::uint32_t& v);
bool get_u64(std::span<const std::uint8_t> in, std::size_t& off, std::uint64_t& v);
bool get_f64(std::span<const std::uint8_t> in, std::size_t& off, double& v);

}  // namespace jetrace
