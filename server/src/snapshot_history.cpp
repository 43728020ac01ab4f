// SnapshotHistory: baselines and the per-baseline encode cache.
#include "jetrace/server/snapshot_history.hpp"

#include <utility>

namespace jetrace::server {

void SnapshotHistory::clear() {
    sent_.clear();
    by_baseline_.clear();
}

void SnapshotHistory::begin(proto::WorldSnapshot now) {
    now_ = std::move(now);
    by_baseline_.clear();
}

const std::vector<std::uint8_t>& SnapshotHistory::encoded_for(std::uint32_t acked_tick, std::uint32_t& baseline_tick) {
    const proto::WorldSnapshot* base = sent_.find(acked_tick);
    baseline_tick = base ? acked_tick : proto::kNoTick;
    auto it = by_baseline_.find(baseline_tick);
    if (it == by_baseline_.end()) it = by_baseline_.emplace(baseline_tick, proto::encode_world(now_, base)).first;
    return it->second;
}

void SnapshotHistory::commit() {
    const std::uint32_t tick = now_.state.tick;
    sent_.insert(tick) = std::move(now_);
    by_baseline_.clear();
}

}  // namespace jetrace::server
