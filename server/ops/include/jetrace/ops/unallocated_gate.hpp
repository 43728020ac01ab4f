// Before Agones allocates the GameServer, jetrace-server takes no players:
// this gate owns the transport until then, refuses every Hello with a
// reason the client shows, and drops connections that stay silent.
#pragma once

#include "jetrace/net/transport.hpp"

#include <cstdint>
#include <map>
#include <vector>

namespace jetrace::ops {

/// The refusal a client gets before the allocation.
inline constexpr const char* kUnallocatedReason =
    "not allocated yet: this game server takes players once Agones allocates it";

class UnallocatedGate {
public:
    /// `hello_timeout_ms`: a connection without a Hello is dropped after it.
    explicit UnallocatedGate(std::uint64_t hello_timeout_ms) : hello_timeout_ms_(hello_timeout_ms) {}
    /// Handles the network (real-time `now_ms`); never blocks.
    void service(net::Transport& transport, std::uint64_t now_ms);
    /// Disconnects every connection left: the race server that takes over
    /// the transport starts with none (it never saw them connect).
    void close_all(net::Transport& transport);
    /// Hellos refused so far.
    std::uint64_t refused() const { return refused_; }

private:
    std::uint64_t hello_timeout_ms_;
    std::map<net::PeerId, std::uint64_t> connected_ms_;
    std::vector<net::Event> events_;
    std::uint64_t refused_ = 0;
};

}  // namespace jetrace::ops
