#include "live_json.hpp"

#include "json_parts.hpp"

#include "jetrace/core/race.hpp"

namespace jetrace::view {

namespace {

using namespace json_parts;

std::string name_of(const LiveRace& s, int slot) {
    if (slot == s.client().slot()) return s.driver();
    for (const proto::PlayerInfo& p : s.client().players()) {
        if (p.slot == slot && !p.name.empty()) return p.name;
    }
    return "car " + std::to_string(slot);
}

json roster_json(const LiveRace& s) {
    json out = json::array();
    for (const proto::PlayerInfo& p : s.client().players()) {
        out.push_back({{"slot", p.slot}, {"name", name_of(s, p.slot)}});
    }
    return out;
}

/// Every active car of the client's world where the client draws it:
/// watching, as interpolated; driving, the own car predicted, the others
/// at the newest snapshot's state drawn where the client interpolates them.
json cars_json(const LiveRace& s, const WorldState& predicted) {
    const client::RaceClient& c = s.client();
    const WorldState& server = c.authoritative();
    json out = json::array();
    for (std::size_t i = 0; i < predicted.cars.size(); ++i) {
        if (!predicted.cars[i].active) continue;
        if (!s.driving()) {
            json j = car_json(predicted.cars[i], i);
            j["own"] = false;
            out.push_back(std::move(j));
            continue;
        }
        const int slot = static_cast<int>(i);
        const bool own = slot == c.slot();
        const CarState& car = own || i >= server.cars.size() ? predicted.cars[i] : server.cars[i];
        json j = car_json(car, i);
        j["p"] = vec(own ? c.visual_own_position() : c.visual_position(slot));
        j["own"] = own;
        out.push_back(std::move(j));
    }
    return out;
}

json standings_json(const LiveRace& s, const WorldState& w) {
    const client::RaceClient& c = s.client();
    const int rate = c.scene().physics.tick_rate_hz;
    const auto order = standings(c.scene().track, w.cars, w.start_tick, rate);
    const int leader = order.empty() ? -1 : order.front().slot;
    const std::uint32_t known = c.authoritative().tick;
    json out = json::array();
    int pos = 1;
    for (const Standing& st : order) {
        out.push_back({{"pos", pos++}, {"slot", st.slot}, {"name", name_of(s, st.slot)}, {"lap", st.lap},
                       {"finished", st.finished},
                       {"finish_s", st.finished ? json(rounded(st.finish_time_s, 0.001)) : json(nullptr)},
                       {"gap_s", optional_s(s.timing().gap_s(st.slot, leader, known, rate))},
                       {"best_lap_s", optional_s(s.timing().best_lap_s(st.slot, known, rate))}});
    }
    return out;
}

/// Watching: the render tick (fractional) and the snapshot ticks the cars
/// are interpolated between, for anyone to check them against the race.
json render_json(const LiveRace& s) {
    if (s.driving()) return nullptr;
    std::uint32_t from = 0, to = 0;
    const bool between = s.client().render_span(from, to);
    return {{"tick", s.client().render_tick()}, {"from", between ? json(from) : json(nullptr)},
            {"to", between ? json(to) : json(nullptr)}};
}

std::string connection_of(const client::RaceClient& c) {
    using client::ClientState;
    switch (c.state()) {
        case ClientState::closed: return "closed: " + c.close_reason();
        case ClientState::reconnecting: return "reconnecting";
        default: return "connected";
    }
}

/// The newest tick whose drawn own car was compared with the server's: where
/// it was drawn (exact doubles), whether that was the server's position bit
/// for bit, and if not, the likely cause; null before the first.
json drawn_json(const client::RaceClient& c) {
    const client::DrawnTick& d = c.last_drawn();
    if (d.tick == proto::kNoTick) return nullptr;
    return {{"tick", d.tick}, {"p", vec(d.drawn)}, {"same", d.same}, {"smoothing", d.smoothing},
            {"cause", client::to_string(d.cause)}};
}

/// The connection as the driver sees it: the round trip (the transport's,
/// or measured in ticks where it has none), the prediction's corrections
/// and where the own car was drawn against the server's position.
json net_json(const client::RaceClient& c) {
    const client::ClientStats& st = c.stats();
    const double rtt = c.rtt_ms() > 0 ? c.rtt_ms() : st.tick_round_trip_ms;
    return {{"rtt_ms", rounded(rtt, 0.1)},
            {"snapshots", st.snapshots},
            {"corrections", st.corrections},
            {"corrections_late", st.corrections_late},
            {"corrections_near_car", st.corrections_near_car},
            {"late_inputs", st.late_inputs},
            {"clock_resyncs", st.clock_resyncs},
            {"max_correction_m", rounded(st.max_correction_m, 0.001)},
            {"drawn_checked", st.drawn_checked},
            {"drawn_off", st.drawn_off},
            {"drawn_off_unexplained", st.drawn_off_unexplained},
            {"drawn", drawn_json(c)}};
}

}  // namespace

std::string live_hello_json(const LiveRace& s) {
    const client::RaceClient& c = s.client();
    const WorldState w = s.world();
    const json j = {{"type", "hello"},
                    {"mode", s.driving() ? "drive" : "live"},
                    {"driver", s.driving() ? json(s.driver()) : json(nullptr)},
                    {"own_slot", c.slot()},
                    {"track", track_json(c.scene().track)},
                    {"car_radius_m", c.scene().physics.car_radius_m},
                    {"tick_rate_hz", c.scene().physics.tick_rate_hz},
                    {"first_tick", nullptr},
                    {"last_tick", nullptr},
                    {"start_tick", w.start_tick},
                    {"laps", w.laps},
                    {"end_reason", nullptr},
                    {"cars", roster_json(s)},
                    {"ghosts", json::array()}};
    return text_of(j);
}

std::string live_frame_json(const LiveRace& s) {
    const client::RaceClient& c = s.client();
    const WorldState w = s.world();
    const int rate = c.scene().physics.tick_rate_hz;
    const double race_s = (static_cast<double>(w.tick) - w.start_tick) / rate;
    const bool counting = c.phase() == proto::RacePhase::countdown && w.tick < w.start_tick;
    const json j = {{"type", "frame"},
                    {"tick", w.tick},
                    {"race_s", rounded(race_s, 0.001)},
                    {"phase", proto::to_string(c.phase())},
                    {"countdown_s", counting ? json(rounded(-race_s, 0.001)) : json(nullptr)},
                    {"laps", w.laps},
                    {"own_slot", c.slot()},
                    {"connection", connection_of(c)},
                    {"net", net_json(c)},
                    {"input", s.driving() ? json{{"throttle", s.input().throttle}, {"steer", s.input().steer},
                                                 {"brake", s.input().brake}}
                                          : json(nullptr)},
                    {"playing", true},
                    {"speed", 1},
                    {"render", render_json(s)},
                    {"cars", cars_json(s, w)},
                    {"standings", standings_json(s, w)},
                    {"ghosts", json::array()}};
    return text_of(j);
}

}  // namespace jetrace::view
