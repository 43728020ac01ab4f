// Where the client drew its own car at each tick it predicted, checked
// against the server's position for that tick when the tick's snapshot
// arrives: what the player saw against what the server ran.
//
// The drawn position is the prediction plus the fading correction offset
// (Interpolator::own), kept as it was right after the tick was predicted: a
// later reconciliation moves the prediction but not what was drawn (the
// offset takes up the difference). A tick is compared once, bit for bit.
#pragma once

#include "jetrace/core/tick_ring.hpp"
#include "jetrace/core/world.hpp"
#include "jetrace/proto/messages.hpp"

#include <cstdint>

namespace jetrace::client {

/// Why the own car's prediction can miss the server's: the snapshot's
/// tick's, or else, while a correction offset fades, the reconciliation's
/// that left it.
enum class DrawnCause : std::uint8_t {
    /// Nothing known: unexplained.
    none = 0,
    /// The snapshot shows a tick the server stepped without the own input.
    late_input = 1,
    /// Another car was within 4 car radii in the snapshot: its inputs were
    /// guessed, and a touch with it was mispredicted.
    near_car = 2,
};

const char* to_string(DrawnCause c);

/// The newest tick compared.
struct DrawnTick {
    std::uint32_t tick = proto::kNoTick;
    /// Where the own car was drawn (unit: m).
    Vec3 drawn{0, 0, 0};
    /// Drawn exactly where the server had it, bit for bit.
    bool same = false;
    /// Drawn with a correction offset (which was fading).
    bool smoothing = false;
    /// Not the same: why (none: unexplained).
    DrawnCause cause = DrawnCause::none;
};

class DrawnCheck {
public:
    void clear() { drawn_.clear(); }
    /// The own car was drawn at `p` for `tick`; `smoothing`: with a
    /// correction offset, left by a reconciliation of cause `offset_cause`.
    /// A tick recorded again (the clock went back) keeps its first drawing.
    void record(std::uint32_t tick, const Vec3& p, bool smoothing, DrawnCause offset_cause) {
        if (!drawn_.has(tick)) drawn_.insert(tick, Drawn{p, smoothing, offset_cause, false});
    }
    /// The server had the own car at `server` at `tick`; `cause`: why the
    /// prediction may have missed it at that tick (late_input, near_car or
    /// none). False: no drawing of that tick is kept, or it was compared
    /// already.
    bool confirm(std::uint32_t tick, const Vec3& server, DrawnCause cause);
    const DrawnTick& last() const { return last_; }

private:
    struct Drawn {
        Vec3 p{0, 0, 0};
        bool smoothing = false;
        DrawnCause offset_cause = DrawnCause::none;
        bool compared = false;
    };
    TickRing<Drawn, 256> drawn_;
    DrawnTick last_;
};

}  // namespace jetrace::client
