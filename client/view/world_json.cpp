#include "world_json.hpp"

#include "jetrace/race.hpp"

#include <nlohmann/json.hpp>

#include <bit>
#include <cmath>

namespace jetrace::view {

namespace {

using nlohmann::json;

/// Names and paths are untrusted bytes (a replay's player names carry no
/// encoding): invalid UTF-8 becomes U+FFFD instead of an exception.
std::string text_of(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

json vec(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }

/// Directions and speeds need no more than 1e-4 for drawing: fewer bytes.
double rounded(double v, double step) { return std::round(v / step) * step; }
json unit(const Vec3& v) { return json::array({rounded(v.x(), 1e-4), rounded(v.y(), 1e-4), rounded(v.z(), 1e-4)}); }

std::string name_of(const ReplayPlayer& r, std::size_t slot) {
    const auto& names = r.header().names;
    if (slot < names.size() && !names[slot].empty()) return names[slot];
    return "car " + std::to_string(slot);
}

json gates_json(const Track& t) {
    json out = json::array();
    for (const Checkpoint& g : t.checkpoints) {
        out.push_back({{"center", vec(g.center)}, {"normal", vec(g.normal)}, {"across", vec(g.across)},
                       {"up", vec(g.up)}, {"half_width_m", g.half_width_m}, {"half_height_m", g.half_height_m}});
    }
    return out;
}

json roster_json(const ReplayPlayer& r) {
    json out = json::array();
    for (std::size_t s = 0; s < r.header().initial.cars.size(); ++s) {
        if (r.header().initial.cars[s].active) out.push_back({{"slot", s}, {"name", name_of(r, s)}});
    }
    return out;
}

json car_json(const CarState& c, std::size_t slot) {
    return {{"slot", slot}, {"p", vec(c.position)}, {"f", unit(c.forward())}, {"u", unit(c.up())},
            {"speed", rounded(c.velocity.norm(), 0.01)}, {"lap", c.lap}, {"gate", c.next_checkpoint},
            {"finished", c.finished}};
}

json cars_json(const WorldState& s) {
    json out = json::array();
    for (std::size_t i = 0; i < s.cars.size(); ++i) {
        if (s.cars[i].active) out.push_back(car_json(s.cars[i], i));
    }
    return out;
}

json optional_s(const std::optional<double>& v) { return v ? json(rounded(*v, 0.001)) : json(nullptr); }

json standings_json(const ReplayPlayer& r, const WorldState& s) {
    const int rate = r.scene().physics.tick_rate_hz;
    const auto order = standings(r.scene().track, s.cars, s.start_tick, rate);
    json out = json::array();
    const int leader = order.empty() ? -1 : order.front().slot;
    int pos = 1;
    for (const Standing& st : order) {
        const RaceTiming& t = r.timing();
        out.push_back({{"pos", pos++}, {"slot", st.slot}, {"name", name_of(r, static_cast<std::size_t>(st.slot))},
                       {"lap", st.lap}, {"finished", st.finished},
                       {"finish_s", st.finished ? json(rounded(st.finish_time_s, 0.001)) : json(nullptr)},
                       {"gap_s", optional_s(t.gap_s(st.slot, leader, s.tick, rate))},
                       {"best_lap_s", optional_s(t.best_lap_s(st.slot, s.tick, rate))}});
    }
    return out;
}

}  // namespace

std::string phase_of(const ReplayPlayer& r, const WorldState& s) {
    if (s.tick < s.start_tick) return "countdown";
    bool all = true, any = false;
    for (const CarState& c : s.cars) {
        if (!c.active) continue;
        any = true;
        all = all && c.finished;
    }
    if ((any && all) || (r.complete() && s.tick == r.last_tick())) return "finished";
    return "racing";
}

std::string hello_json(const Playback& p) {
    const ReplayPlayer& r = p.main();
    const Track& t = r.scene().track;
    json ghosts = json::array();
    for (std::size_t i = 0; i < p.ghost_count(); ++i) {
        ghosts.push_back({{"index", i}, {"file", p.ghost(i).path()}, {"cars", roster_json(p.ghost(i))}});
    }
    const json j = {{"type", "hello"},
                    {"mode", "replay"},
                    {"file", r.path()},
                    {"track", {{"name", t.name}, {"triangles", t.triangles.size()}, {"gates", gates_json(t)},
                               {"bounds", {{"min", vec(t.bounds.min)}, {"max", vec(t.bounds.max)}}}}},
                    {"car_radius_m", r.scene().physics.car_radius_m},
                    {"tick_rate_hz", r.scene().physics.tick_rate_hz},
                    {"first_tick", r.first_tick()},
                    {"last_tick", r.last_tick()},
                    {"start_tick", r.start_tick()},
                    {"laps", r.header().initial.laps},
                    {"end_reason", r.complete() ? json(replay::end_reason_name(r.trailer().reason)) : json(nullptr)},
                    {"cars", roster_json(r)},
                    {"ghosts", ghosts}};
    return text_of(j);
}

std::string frame_json(const Playback& p) {
    const ReplayPlayer& r = p.main();
    const WorldState& s = p.main_state();
    json ghosts = json::array();
    for (std::size_t i = 0; i < p.ghost_count(); ++i) {
        ghosts.push_back({{"index", i}, {"tick", p.ghost_state(i).tick}, {"cars", cars_json(p.ghost_state(i))}});
    }
    const double race_s = (static_cast<double>(s.tick) - s.start_tick) / r.scene().physics.tick_rate_hz;
    const json j = {{"type", "frame"},       {"tick", s.tick},
                    {"race_s", rounded(race_s, 0.001)},
                    {"phase", phase_of(r, s)}, {"playing", p.playing()},
                    {"speed", p.speed()},      {"cars", cars_json(s)},
                    {"standings", standings_json(r, s)},
                    {"ghosts", ghosts}};
    return text_of(j);
}

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
