// Welcome.physics: jetrace::PhysicsSettings <-> its flatbuffers table.
#pragma once

#include "jetrace/core/settings.hpp"
#include "jetrace_generated.h"

#include <string>

namespace jetrace::proto {

flatbuffers::Offset<wire::PhysicsSettings> encode_physics(flatbuffers::FlatBufferBuilder& b, const PhysicsSettings& s);
/// False with why if a field is out of its type's range (an enum value the
/// core does not have, a non-finite number); validate() is the caller's.
bool decode_physics(const wire::PhysicsSettings& t, PhysicsSettings& out, std::string& why);

}  // namespace jetrace::proto
