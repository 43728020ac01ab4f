// ServerConfig: its checks (against ServerLimits) and the default snapshot rate.
#include "jetrace/server/race_server.hpp"

#include <algorithm>
#include <sstream>

namespace jetrace::server {

namespace {

void check(std::ostringstream& err, double v, const ValueRange& r, const char* what, const char* unit = "") {
    if (!r.contains(v)) err << what << " must be in " << r.text() << unit << "; ";
}

}  // namespace

std::string validate(const ServerConfig& c, int tick_rate_hz) {
    using L = ServerLimits;
    std::ostringstream err;
    check(err, c.laps, L::laps, "laps");
    check(err, c.max_players, L::players, "max players");
    check(err, c.max_observers, L::observers, "max observers");
    if (c.min_players < 1 || c.min_players > c.max_players) err << "min players must be in [1, max players]; ";
    if (c.snapshot_rate_hz < 1 || c.snapshot_rate_hz > tick_rate_hz || tick_rate_hz % c.snapshot_rate_hz != 0)
        err << "snapshot rate must divide the tick rate (" << tick_rate_hz << " Hz; the default snapshot rate is "
            << default_snapshot_rate(tick_rate_hz) << " Hz at this tick rate); ";
    check(err, c.lobby_timeout_s, L::lobby_timeout_s, "lobby timeout", " s");
    check(err, c.lobby_log_interval_s, L::lobby_log_interval_s, "lobby log interval", " s");
    check(err, c.races, L::races, "races");
    check(err, c.countdown_s, L::countdown_s, "countdown", " s");
    check(err, c.results_pause_s, L::results_pause_s, "results pause", " s");
    check(err, c.finish_window_s, L::finish_window_s, "finish window", " s");
    check(err, c.max_race_s, L::max_race_s, "max race time", " s");
    check(err, c.max_input_lead_ticks, L::max_input_lead_ticks, "max input lead", " ticks (the input ring's size, less one)");
    check(err, c.input_hold_s, L::input_hold_s, "input hold", " s");
    check(err, c.hello_timeout_s, L::hello_timeout_s, "hello timeout", " s");
    check(err, c.reconnect_grace_s, L::reconnect_grace_s, "reconnect grace", " s");
    check(err, c.linger_s, L::linger_s, "linger", " s");
    if (c.race_id.size() > auth::kMaxRaceIdBytes || !proto::valid_text(c.race_id))
        err << "race id must be at most 64 bytes of UTF-8 text; ";
    check(err, static_cast<double>(c.max_connect_nonces), L::max_connect_nonces, "max connect nonces");
    return err.str();
}

int default_snapshot_rate(int tick_rate_hz) {
    for (int r = std::min(60, tick_rate_hz); r > 1; --r) {
        if (tick_rate_hz % r == 0) return r;
    }
    return 1;
}

}  // namespace jetrace::server
