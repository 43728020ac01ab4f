// What a race looks like from outside, tick by tick. RaceServer calls its
// observer from update() as the race runs; the observer does what the
// library does not (files: ReplayRecorder writes the replay). An observer
// must not call back into the server.
#pragma once

#include "jetrace/core/hovercar.hpp"
#include "jetrace/core/world.hpp"
#include "jetrace/replay/format.hpp"

#include <cstdint>
#include <span>

namespace jetrace::server {

class RaceObserver {
public:
    virtual ~RaceObserver() = default;
    /// A race's countdown begins: the track, physics, names and the world at
    /// its first tick.
    virtual void race_started(const replay::Header& header) = 0;
    /// Tick `tick` is about to be stepped: the cars removed before it (their
    /// players left for good) and every slot's input.
    virtual void before_step(std::uint32_t tick, std::span<const std::uint8_t> removed,
                             std::span<const Input> inputs) = 0;
    /// The step is done: the world after it.
    virtual void after_step(const WorldState& after) = 0;
    /// The race ended: final tick, hash, why, results.
    virtual void race_ended(const replay::Trailer& trailer) = 0;
    /// The server stopped; a race begun and not ended gets no trailer.
    virtual void stopped() = 0;
};

}  // namespace jetrace::server
