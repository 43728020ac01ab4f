// The compiled track file (.jtrack, docs/TRACKS.md "Compiled tracks"): a
// track's shared vertices, u32 triangle indices, gates, spawns, kill height
// and name in one little-endian binary, checked by CRC-32C. Reading it is a
// memory map, bounds and range checks, the checksum and Triangle::make per
// triangle: no text parsing. The track read back has the same triangles (bit
// for bit, in the same order), gates, spawns and kill height as the one
// written, so the same identity() and the same races.
//
// A .jtrack file is untrusted input: every size is checked against the file
// size before it is used, every index against the vertex count, every
// number for finiteness and range; any problem comes back as an error
// message naming it, never a crash.
#pragma once

#include "jetrace/core/track.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace jetrace {

/// The file's first 8 bytes.
inline constexpr char kJtrackMagic[8] = {'J', 'T', 'R', 'A', 'C', 'K', '\r', '\n'};
/// The only version this reader accepts.
inline constexpr std::uint32_t kJtrackVersion = 1;
/// Size of the fixed header (unit: bytes).
inline constexpr std::size_t kJtrackHeaderBytes = 64;
/// Most bytes of a track name.
inline constexpr std::uint32_t kJtrackMaxNameBytes = 4096;
/// Most gates and most spawns a file may hold.
inline constexpr std::uint32_t kJtrackMaxGates = 100'000;
inline constexpr std::uint32_t kJtrackMaxSpawns = 100'000;

/// True if `bytes` starts with the .jtrack magic.
bool is_jtrack(std::span<const std::uint8_t> bytes);

/// The .jtrack bytes of `track` (vertices shared by exact bit pattern, in
/// order of first use). Deterministic: the same track gives the same bytes.
std::vector<std::uint8_t> encode_jtrack(const Track& track);

/// Reads .jtrack bytes into `out`. False and `error` set (naming the field,
/// the offset or the index that is wrong) on any bad input.
bool decode_jtrack(std::span<const std::uint8_t> bytes, Track& out, std::string& error);

/// Writes encode_jtrack(track) to `path` (through a temporary file renamed
/// into place). False and `error` set if anything fails.
bool write_jtrack_file(const Track& track, const std::string& path, std::string& error);

/// Maps `path` read-only and decodes it (decode_jtrack); errors start with
/// the path.
bool load_jtrack_file(const std::string& path, Track& out, std::string& error);

/// True if the file at `path` starts with the .jtrack magic (false when it
/// cannot be read).
bool file_is_jtrack(const std::string& path);

}  // namespace jetrace
