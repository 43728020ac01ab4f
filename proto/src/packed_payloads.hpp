// The bit-packed [ubyte] payloads of InputBatch and Snapshot, the two
// messages sent many times a second (docs/PROTOCOL.md, "Messages", sections
// "InputBatch" and "Snapshot"). messages.cpp wraps them in their flatbuffers
// tables. Internal to jetrace::proto.
#pragma once

#include "jetrace/proto/messages.hpp"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace jetrace::proto::packed {

/// Asserts the rules unpack() checks, so whatever pack() produces unpacks.
std::vector<std::uint8_t> pack(const InputBatch& m);
/// The header fields, then m.world (whose first field is the server tick).
std::vector<std::uint8_t> pack(const Snapshot& m);

/// Untrusted bytes. False with "Message.field: reason" in `error`.
bool unpack(std::span<const std::uint8_t> bytes, InputBatch& m, std::string& error);
bool unpack(std::span<const std::uint8_t> bytes, Snapshot& m, std::string& error);

}  // namespace jetrace::proto::packed
