// One player's inputs on their way into the simulation: what the server
// accepts from InputBatches (one input per tick, the first one received,
// within the lead limit), which input steps each tick (a missing one repeats
// the last for a while, then neutral), and what is known of the coming ticks
// (relayed in snapshots).
#pragma once

#include "jetrace/core/hovercar.hpp"
#include "jetrace/core/tick_ring.hpp"
#include "jetrace/proto/messages.hpp"

#include <cstdint>
#include <vector>

namespace jetrace::server {

class InputQueue {
public:
    /// Ticks of inputs held. The lead limit must stay below it, or an input
    /// for a tick ahead would take the slot of one still to be stepped.
    static constexpr std::size_t kRing = 256;
    static constexpr int kMaxLeadTicks = static_cast<int>(kRing) - 1;

    /// What accept() saw in one batch.
    struct Accepted {
        /// Inputs for ticks already stepped that had not arrived in time.
        std::uint64_t late = 0;
        /// Inputs beyond the lead limit, dropped.
        std::uint64_t dropped = 0;
        /// The first tick beyond the lead limit (kNoTick: none).
        std::uint32_t too_far_tick = proto::kNoTick;
        /// A tick whose second input differed from the first (kNoTick: none).
        std::uint32_t conflicting_tick = proto::kNoTick;
    };

    /// Forgets everything: a new race or a new connection starts from here.
    void reset();

    /// Takes the inputs of `b` for ticks from `now_tick` up to
    /// `now_tick + max_lead_ticks` (at most kMaxLeadTicks).
    Accepted accept(const proto::InputBatch& b, std::uint32_t now_tick, int max_lead_ticks);

    /// The input that steps `tick` (asked once per tick, in order): the one
    /// received, else the last one applied if it stepped a tick at most
    /// `hold_ticks` before, else neutral (`Input{}`). Sets `missing` when
    /// none came.
    Input pick(std::uint32_t tick, std::uint32_t hold_ticks, bool& missing);

    /// The inputs received for `from`, `from + 1`, ... with no gap, at most `max`.
    void upcoming(std::uint32_t from, std::size_t max, std::vector<Input>& out) const;

    /// The newest tick the client produced an input for, capped at the lead
    /// limit (kNoTick: none this race).
    std::uint32_t newest_tick() const { return newest_tick_; }
    /// The newest tick stepped with an input of this client (kNoTick: none).
    std::uint32_t last_applied_tick() const { return last_applied_tick_; }

private:
    TickRing<Input, kRing> ring_;
    std::uint32_t newest_tick_ = proto::kNoTick;
    std::uint32_t last_applied_tick_ = proto::kNoTick;
    Input last_input_{};
};

}  // namespace jetrace::server
