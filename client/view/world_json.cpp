#include "world_json.hpp"

#include "json_parts.hpp"

#include "jetrace/core/race.hpp"

#include <bit>
#include <cmath>

namespace jetrace::view {

namespace {

using namespace json_parts;

std::string name_of(const ReplayPlayer& r, std::size_t slot) {
    const auto& names = r.header().names;
    if (slot < names.size() && !names[slot].empty()) return names[slot];
    return "car " + std::to_string(slot);
}

json roster_json(const ReplayPlayer& r) {
    json out = json::array();
    for (std::size_t s = 0; s < r.header().initial.cars.size(); ++s) {
        if (r.header().initial.cars[s].active) out.push_back({{"slot", s}, {"name", name_of(r, s)}});
    }
    return out;
}

json cars_json(const WorldState& s) {
    json out = json::array();
    for (std::size_t i = 0; i < s.cars.size(); ++i) {
        if (s.cars[i].active) out.push_back(car_json(s.cars[i], i));
    }
    return out;
}

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
                    {"track", track_json(t)},
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

}  // namespace jetrace::view
