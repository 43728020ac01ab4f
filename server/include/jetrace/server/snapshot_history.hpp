// The world snapshots sent in the last kTicks ticks, kept as baselines for
// delta encoding, and the encodings of the current snapshot, shared between
// the clients that acknowledged the same baseline.
#pragma once

#include "jetrace/core/tick_ring.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/proto/world_codec.hpp"

#include <cstdint>
#include <map>
#include <vector>

namespace jetrace::server {

class SnapshotHistory {
public:
    /// Ticks of snapshots kept. A client whose acknowledged snapshot is
    /// older gets a full snapshot instead of a delta.
    static constexpr std::size_t kTicks = proto::kBaselineWindowTicks;

    /// Forgets every snapshot (a new race).
    void clear();

    /// Starts the snapshot of `now.state.tick`: encodings asked for from
    /// here on are of `now`.
    void begin(proto::WorldSnapshot now);
    /// The encoding of the current snapshot against the client's newest
    /// acknowledged one (kNoTick: none), and which baseline it used
    /// (kNoTick: a full snapshot).
    const std::vector<std::uint8_t>& encoded_for(std::uint32_t acked_tick, std::uint32_t& baseline_tick);
    /// Keeps the current snapshot as a baseline.
    void commit();

private:
    TickRing<proto::WorldSnapshot, kTicks> sent_;
    proto::WorldSnapshot now_;
    std::map<std::uint32_t, std::vector<std::uint8_t>> by_baseline_;
};

}  // namespace jetrace::server
