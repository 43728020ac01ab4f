#include "jetrace/replay/fields.hpp"

#include "jetrace/core/car_fields.hpp"
#include "jetrace/core/state_bytes.hpp"

#include <bit>
#include <cstdio>
#include <type_traits>

namespace jetrace::replay {

namespace {

template <class T>
std::string text(T v) {
    if constexpr (std::is_same_v<T, bool>) {
        return v ? "true" : "false";
    } else if constexpr (std::is_same_v<T, double>) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.17g (0x%016llx)", v,
                      static_cast<unsigned long long>(std::bit_cast<std::uint64_t>(v)));
        return buf;
    } else {
        return std::to_string(v);
    }
}

template <class T>
bool same_bits(T x, T y) {
    if constexpr (std::is_same_v<T, double>) {
        return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y);
    } else {
        return x == y;
    }
}

void diff_cars(int slot, const CarState& a, const CarState& b, std::size_t max, std::vector<FieldDifference>& out) {
    // The two visits run in the same order: collect b's values first.
    std::vector<std::string> b_text;
    b_text.reserve(kCarFieldCount);
    visit_car_fields(b, [&](const char*, auto v) { b_text.push_back(text(v)); });
    std::size_t i = 0;
    visit_car_fields(a, [&](const char* name, auto v) {
        const std::string at = text(v);
        if (at != b_text[i] && out.size() < max) out.push_back({slot, name, at, b_text[i]});
        ++i;
    });
}

}  // namespace

std::vector<FieldDifference> diff_states(const WorldState& a, const WorldState& b, std::size_t max) {
    std::vector<FieldDifference> out;
    const auto world = [&](const char* name, auto x, auto y) {
        if (!same_bits(x, y) && out.size() < max) out.push_back({-1, name, text(x), text(y)});
    };
    world("tick", a.tick, b.tick);
    world("start_tick", a.start_tick, b.start_tick);
    world("laps", a.laps, b.laps);
    world("slots", a.cars.size(), b.cars.size());
    const std::size_t n = a.cars.size() < b.cars.size() ? a.cars.size() : b.cars.size();
    for (std::size_t s = 0; s < n && out.size() < max; ++s) diff_cars(static_cast<int>(s), a.cars[s], b.cars[s], max, out);
    return out;
}

bool same_state(const WorldState& a, const WorldState& b) {
    std::vector<std::uint8_t> x, y;
    write_state(a, x);
    write_state(b, y);
    return x == y;
}

std::string describe(const FieldDifference& d) {
    const std::string who = d.slot < 0 ? std::string("world") : "slot " + std::to_string(d.slot);
    return who + " " + d.field + ": " + d.a + " vs " + d.b;
}

}  // namespace jetrace::replay
