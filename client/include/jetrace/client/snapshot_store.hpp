// The snapshots a client received: decoded worlds by tick (the baselines of
// later deltas, and the frames the interpolation draws from), the newest
// one, and what it acknowledges: the newest tick back to the server (its
// next baseline) and the server's last applied input of ours.
#pragma once

#include "jetrace/proto/messages.hpp"
#include "jetrace/proto/world_codec.hpp"

#include <array>
#include <cstdint>
#include <string>

namespace jetrace::client {

class SnapshotStore {
public:
    /// Worlds kept, by tick modulo this: every tick a baseline can be.
    static constexpr std::size_t kKept = proto::kBaselineWindowTicks;
    struct Entry {
        std::uint32_t tick = proto::kNoTick;
        proto::WorldSnapshot world;
    };
    enum class Added : std::uint8_t {
        /// Its baseline is not kept (lost, or too old).
        no_baseline,
        /// It does not decode, or its world is not the one it names.
        undecodable,
        /// Kept, but older than the newest (reordered).
        older,
        /// Kept as the newest.
        newest,
    };

    SnapshotStore() { reset(); }
    /// Forgets every snapshot and acknowledgement.
    void reset();
    /// Decodes `s` against its baseline and keeps it; its world must have
    /// at least `min_cars` cars. `error`: why it did not decode.
    Added add(const proto::Snapshot& s, std::size_t min_cars, std::uint64_t now_us, std::string& error);

    /// The newest snapshot's world (empty before one).
    const proto::WorldSnapshot& latest() const { return latest_; }
    /// When the newest snapshot came (unit: µs of the caller's time).
    std::uint64_t latest_at_us() const { return latest_at_us_; }
    /// The newest snapshot's tick (kNoTick: none), acknowledged to the server.
    std::uint32_t newest_tick() const { return newest_tick_; }
    /// The server's last applied input of ours (kNoTick: none yet).
    std::uint32_t last_applied_input_tick() const { return last_applied_input_tick_; }
    const std::array<Entry, kKept>& entries() const { return kept_; }

private:
    std::array<Entry, kKept> kept_{};
    proto::WorldSnapshot latest_;
    proto::WorldSnapshot decoded_;  // decode target (keeps its storage)
    std::uint64_t latest_at_us_ = 0;
    std::uint32_t newest_tick_ = proto::kNoTick;
    std::uint32_t last_applied_input_tick_ = proto::kNoTick;
};

}  // namespace jetrace::client
