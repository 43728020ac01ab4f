#include "jetrace/client/snapshot_store.hpp"

#include <utility>

namespace jetrace::client {

void SnapshotStore::reset() {
    for (Entry& e : kept_) e.tick = proto::kNoTick;
    newest_tick_ = proto::kNoTick;
    last_applied_input_tick_ = proto::kNoTick;
}

SnapshotStore::Added SnapshotStore::add(const proto::Snapshot& s, std::size_t min_cars, std::uint64_t now_us,
                                        std::string& error) {
    const proto::WorldSnapshot* base = nullptr;
    if (s.baseline_tick != proto::kNoTick) {
        const Entry& e = kept_[s.baseline_tick % kKept];
        if (e.tick != s.baseline_tick) return Added::no_baseline;
        base = &e.world;
    }
    if (!proto::decode_world(s.world, base, decoded_, error) || decoded_.state.tick != s.server_tick ||
        decoded_.state.cars.size() < min_cars) {
        return Added::undecodable;
    }
    Entry& kept = kept_[s.server_tick % kKept];
    kept.tick = s.server_tick;
    std::swap(kept.world, decoded_);  // no copy; decoded_ takes the old entry's storage
    if (newest_tick_ != proto::kNoTick && s.server_tick <= newest_tick_) return Added::older;
    newest_tick_ = s.server_tick;
    if (s.last_applied_input_tick != proto::kNoTick) last_applied_input_tick_ = s.last_applied_input_tick;
    latest_ = kept.world;
    latest_at_us_ = now_us;
    return Added::newest;
}

}  // namespace jetrace::client
