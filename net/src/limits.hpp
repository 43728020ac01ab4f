// Private limits shared by the transport implementations.
#pragma once

#include <cstddef>

namespace jetrace::net::detail {

/// Largest datagram accepted by send() or delivered by service() (unit: bytes).
inline constexpr std::size_t kMaxDatagramBytes = 64 * 1024;

}  // namespace jetrace::net::detail
