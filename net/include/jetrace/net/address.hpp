// "HOST:PORT" command-line addresses (jetrace-bot --connect, jetrace-netsim
// --forward).
#pragma once

#include <cstdint>
#include <string>

namespace jetrace::net {

/// Splits "HOST:PORT" (PORT 1..65535, HOST not empty). False if malformed.
bool split_host_port(const std::string& text, std::string& host, std::uint16_t& port);

}  // namespace jetrace::net
