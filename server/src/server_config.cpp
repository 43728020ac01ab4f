// ServerConfig: its checks and the default snapshot rate.
#include "jetrace/server/race_server.hpp"

#include <algorithm>
#include <sstream>

namespace jetrace::server {

std::string validate(const ServerConfig& c, int tick_rate_hz) {
    std::ostringstream err;
    if (c.laps < 1 || c.laps > 1000) err << "laps must be in [1, 1000]; ";
    if (c.max_players < 1 || c.max_players > proto::kMaxSlots) err << "max players must be in [1, 64]; ";
    if (c.min_players < 1 || c.min_players > c.max_players) err << "min players must be in [1, max players]; ";
    if (c.snapshot_rate_hz < 1 || c.snapshot_rate_hz > tick_rate_hz || tick_rate_hz % c.snapshot_rate_hz != 0)
        err << "snapshot rate must divide the tick rate (" << tick_rate_hz << " Hz; the default snapshot rate is "
            << default_snapshot_rate(tick_rate_hz) << " Hz at this tick rate); ";
    if (!(c.lobby_timeout_s >= 0 && c.lobby_timeout_s <= 86400)) err << "lobby timeout must be in [0, 86400] s; ";
    if (!(c.lobby_log_interval_s > 0 && c.lobby_log_interval_s <= 86400))
        err << "lobby log interval must be in (0, 86400] s; ";
    if (c.races < 0) err << "races must be >= 0; ";
    if (!(c.countdown_s >= 0 && c.countdown_s <= 600)) err << "countdown must be in [0, 600] s; ";
    if (!(c.results_pause_s >= 0 && c.results_pause_s <= 600)) err << "results pause must be in [0, 600] s; ";
    if (!(c.finish_window_s > 0 && c.finish_window_s <= 3600)) err << "finish window must be in (0, 3600] s; ";
    if (!(c.max_race_s > 0 && c.max_race_s <= 86400)) err << "max race time must be in (0, 86400] s; ";
    if (c.max_input_lead_ticks < 1 || c.max_input_lead_ticks > InputQueue::kMaxLeadTicks)
        err << "max input lead must be in [1, " << InputQueue::kMaxLeadTicks << "] ticks (the input ring holds "
            << InputQueue::kRing << "); ";
    if (!(c.hello_timeout_s > 0 && c.hello_timeout_s <= 86400)) err << "hello timeout must be in (0, 86400] s; ";
    if (!(c.reconnect_grace_s >= 0 && c.reconnect_grace_s <= 3600)) err << "reconnect grace must be in [0, 3600] s; ";
    if (c.race_id.size() > auth::kMaxRaceIdBytes || !proto::valid_text(c.race_id))
        err << "race id must be at most 64 bytes of UTF-8 text; ";
    if (c.max_connect_nonces < 1 || c.max_connect_nonces > 10'000'000) err << "max connect nonces must be in [1, 1e7]; ";
    return err.str();
}

int default_snapshot_rate(int tick_rate_hz) {
    for (int r = std::min(60, tick_rate_hz); r > 1; --r) {
        if (tick_rate_hz % r == 0) return r;
    }
    return 1;
}

}  // namespace jetrace::server
