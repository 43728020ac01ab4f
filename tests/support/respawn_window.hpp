// When a client draws a car before a respawn it already knows of: from the
// first snapshot that shows a car's respawn until the render tick reaches
// that snapshot, the car is drawn where it was before (Interpolator), not
// near its newest position. Live tests that bound the distance between the
// drawn and the newest position check this window against the position
// before the respawn instead.
#pragma once

#include "jetrace/core/world.hpp"

#include <cstdint>
#include <vector>

namespace jetrace::test {

class RespawnWindows {
public:
    /// Feeds a client's newest authoritative world (every step; the same
    /// world again changes nothing). A car's first count, and a lower one (a
    /// new race), open no window.
    void see(const WorldState& newest) {
        if (slots_.size() < newest.cars.size()) slots_.resize(newest.cars.size());
        for (std::size_t s = 0; s < newest.cars.size(); ++s) {
            Slot& slot = slots_[s];
            const CarState& car = newest.cars[s];
            if (!slot.known) {
                slot.known = true;  // first seen: no respawn to draw before
            } else if (car.respawns > slot.respawns) {
                slot.shown_at_tick = newest.tick;
                slot.before = slot.last;
            } else if (car.respawns < slot.respawns) {
                slot.shown_at_tick = 0;
            }
            slot.respawns = car.respawns;
            slot.last = car.position;
        }
    }
    /// True if car `s` is drawn at `render_tick` before a respawn the newest
    /// world shows.
    bool drawn_before_respawn(std::size_t s, double render_tick) const {
        return s < slots_.size() && render_tick < static_cast<double>(slots_[s].shown_at_tick);
    }
    /// Where car `s` was in the newest world seen before its last respawn.
    Vec3 before(std::size_t s) const { return s < slots_.size() ? slots_[s].before : Vec3::Zero(); }

private:
    struct Slot {
        bool known = false;
        std::uint32_t respawns = 0;
        std::uint32_t shown_at_tick = 0;
        Vec3 before{0, 0, 0};
        Vec3 last{0, 0, 0};
    };
    std::vector<Slot> slots_;
};

}  // namespace jetrace::test
