// InputQueue: the acceptance rules and the per-tick pick (docs/PROTOCOL.md,
// "Timing and input flow").
#include "jetrace/server/input_queue.hpp"

#include <algorithm>
#include <cassert>

namespace jetrace::server {

void InputQueue::reset() {
    ring_.clear();
    newest_tick_ = proto::kNoTick;
    last_applied_tick_ = proto::kNoTick;
    last_input_ = Input{};
}

InputQueue::Accepted InputQueue::accept(const proto::InputBatch& b, std::uint32_t now_tick, int max_lead_ticks) {
    assert(max_lead_ticks >= 1 && max_lead_ticks <= kMaxLeadTicks);
    Accepted out;
    if (b.inputs.empty()) return out;
    const std::uint64_t now = now_tick;
    const std::uint64_t limit = now + static_cast<std::uint64_t>(max_lead_ticks);
    // The newest tick the client has produced an input for, late or not: the
    // margin fed back in snapshots tells it to run further ahead. Beyond the
    // lead limit it counts as the limit, so a client that ran too far ahead
    // learns it (and slows down) instead of hearing stale news forever.
    const std::uint64_t newest = std::min(std::uint64_t{b.first_tick} + b.inputs.size() - 1, limit);
    if (newest_tick_ == proto::kNoTick || newest > newest_tick_) newest_tick_ = static_cast<std::uint32_t>(newest);
    for (std::size_t i = 0; i < b.inputs.size(); ++i) {
        const std::uint64_t t = std::uint64_t{b.first_tick} + i;
        if (t < now) {
            // Too late: that tick is simulated. A redundant copy of an input
            // that came in time is not late.
            if (now - t < kRing && !ring_.has(static_cast<std::uint32_t>(t))) ++out.late;
            continue;
        }
        if (t > limit) {
            out.too_far_tick = static_cast<std::uint32_t>(std::min<std::uint64_t>(t, proto::kNoTick - 1));
            out.dropped += b.inputs.size() - i;
            break;
        }
        const auto tick = static_cast<std::uint32_t>(t);
        // One input per tick, the first one received: redundant copies are
        // identical, and a client sending different ones for the same tick
        // (a speed hack, or spoiling the inputs already relayed to the
        // others as upcoming) changes nothing.
        if (const Input* kept = ring_.find(tick)) {
            if (kept->pack() != b.inputs[i].pack() && out.conflicting_tick == proto::kNoTick) out.conflicting_tick = tick;
            continue;
        }
        ring_.insert(tick, b.inputs[i]);
    }
    return out;
}

Input InputQueue::pick(std::uint32_t tick, std::uint32_t hold_ticks, bool& missing) {
    missing = true;
    if (const Input* got = ring_.find(tick)) {
        last_input_ = *got;
        last_applied_tick_ = tick;
        missing = false;
        return last_input_;
    }
    if (last_applied_tick_ == proto::kNoTick || tick - last_applied_tick_ > hold_ticks) return Input{};
    return last_input_;
}

void InputQueue::upcoming(std::uint32_t from, std::size_t max, std::vector<Input>& out) const {
    for (std::uint32_t t = from; out.size() < max; ++t) {
        const Input* got = ring_.find(t);
        if (!got) break;
        out.push_back(*got);
    }
}

}  // namespace jetrace::server
