// TickRing<T, N>: the last N values of a tick-indexed stream (yojimbo's
// SequenceBuffer is the model). Slot `tick % N` holds the value of one tick
// and remembers which: a lookup of a tick that was never stored, or whose
// slot a later tick took over, finds nothing. Ticks are u32, as on the wire;
// kNoTick (0xFFFFFFFF) is never a stored tick.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace jetrace {

template <typename T, std::size_t N>
class TickRing {
    static_assert(N > 0 && (N & (N - 1)) == 0, "a power of two, so tick % N survives the u32 wrap");

public:
    static constexpr std::size_t kSize = N;
    static constexpr std::uint32_t kNoTick = 0xFFFFFFFFu;

    TickRing() { clear(); }

    /// Forgets every tick (the values stay allocated).
    void clear() { ticks_.fill(kNoTick); }

    bool has(std::uint32_t tick) const { return tick != kNoTick && ticks_[tick % N] == tick; }

    /// The value stored for `tick`, or nullptr.
    const T* find(std::uint32_t tick) const { return has(tick) ? &values_[tick % N] : nullptr; }
    T* find(std::uint32_t tick) { return has(tick) ? &values_[tick % N] : nullptr; }

    /// The slot of `tick`, now holding it (whatever tick it held before).
    T& insert(std::uint32_t tick) {
        ticks_[tick % N] = tick;
        return values_[tick % N];
    }
    void insert(std::uint32_t tick, const T& value) { insert(tick) = value; }

private:
    std::array<T, N> values_{};
    std::array<std::uint32_t, N> ticks_{};
};

}  // namespace jetrace
