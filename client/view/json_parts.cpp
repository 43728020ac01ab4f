#include "json_parts.hpp"

#include <bit>
#include <cmath>

namespace jetrace::view::json_parts {

std::string text_of(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

double rounded(double v, double step) { return std::round(v / step) * step; }

json unit(const Vec3& v) { return json::array({rounded(v.x(), 1e-4), rounded(v.y(), 1e-4), rounded(v.z(), 1e-4)}); }

json optional_s(const std::optional<double>& v) { return v ? json(rounded(*v, 0.001)) : json(nullptr); }

json track_json(const Track& t) {
    json gates = json::array();
    for (const Checkpoint& g : t.checkpoints) {
        gates.push_back({{"center", vec(g.center)}, {"normal", vec(g.normal)}, {"across", vec(g.across)},
                         {"up", vec(g.up)}, {"half_width_m", g.half_width_m}, {"half_height_m", g.half_height_m}});
    }
    return {{"name", t.name}, {"triangles", t.triangles.size()}, {"gates", gates},
            {"bounds", {{"min", vec(t.bounds.min)}, {"max", vec(t.bounds.max)}}}};
}

json car_json(const CarState& c, std::size_t slot) {
    return {{"slot", slot}, {"p", vec(c.position)}, {"f", unit(c.forward())}, {"u", unit(c.up())},
            {"speed", rounded(c.velocity.norm(), 0.01)}, {"lap", c.lap}, {"gate", c.next_checkpoint},
            {"finished", c.finished}};
}

}  // namespace jetrace::view::json_parts

namespace jetrace::view {

std::vector<std::uint8_t> track_mesh_bytes(const Track& track) {
    std::vector<std::uint8_t> out;
    out.reserve(track.triangles.size() * 36);
    const auto put = [&out](double v) {
        const auto bits = std::bit_cast<std::uint32_t>(static_cast<float>(v));
        for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
    };
    for (const Triangle& t : track.triangles) {
        for (const Vec3* v : {&t.a, &t.b, &t.c}) {
            put(v->x());
            put(v->y());
            put(v->z());
        }
    }
    return out;
}

}  // namespace jetrace::view
