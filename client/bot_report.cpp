// jetrace-bot's outcomes and JSON lines.
#include "bot_report.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>

namespace jetrace::bot {

ExitCode outcome_of(const client::RaceClient& c, bool finished, bool stopped) {
    if (finished) return kFinished;
    using proto::CloseClass;
    const std::uint16_t code = c.close_code();
    if (proto::close_class(code) == CloseClass::refused) return kRefused;
    // Not the server's track or physics, or a track download that failed:
    // --track with the server's track file races.
    if (code == static_cast<std::uint16_t>(proto::CloseCode::local_incompatible) ||
        code == static_cast<std::uint16_t>(proto::CloseCode::local_bad_track)) {
        return kBadArguments;
    }
    if (stopped) return kStopped;
    // The server said goodbye: it shut down, drained, cancelled its lobby, or dropped the bot.
    if (proto::close_class(code) == CloseClass::normal || proto::close_class(code) == CloseClass::remote_fault)
        return kServerGone;
    if (c.races_finished() > 0) return kDidNotFinish;
    return kLostConnection;
}

const char* outcome_name(ExitCode code) {
    switch (code) {
        case kFinished: return "finished";
        case kDidNotFinish: return "did_not_finish";
        case kBadArguments: return "incompatible";
        case kRefused: return "refused";
        case kLostConnection: return "lost_connection";
        case kServerGone: return "server_gone";
        case kStopped: return "stopped";
    }
    return "unknown";
}

ExitCode combine(ExitCode a, ExitCode b) {
    // Most telling first: what the user must fix, then what went wrong.
    for (ExitCode c : {kBadArguments, kRefused, kServerGone, kLostConnection, kStopped, kDidNotFinish}) {
        if (a == c || b == c) return c;
    }
    return kFinished;
}

bool print_bot_line(const client::RaceClient& c, const std::string& name, bool stopped, double wall_s,
                    ExitCode& code) {
    const auto& r = c.results();
    int position = 0;
    bool finished = false;
    for (std::size_t i = 0; i < r.standings.size(); ++i) {
        if (r.standings[i].slot == c.slot() && r.standings[i].name == name) {
            position = static_cast<int>(i) + 1;
            finished = r.standings[i].finished;
        }
    }
    code = outcome_of(c, finished, stopped);
    const auto totals = c.totals();
    nlohmann::json j;
    j["name"] = name;
    j["finished"] = finished;
    j["position"] = position;
    j["outcome"] = outcome_name(code);
    j["corrections"] = c.stats().corrections;
    j["corrections_late"] = c.stats().corrections_late;
    j["corrections_near_car"] = c.stats().corrections_near_car;
    j["max_correction_m"] = c.stats().max_correction_m;
    j["snapshots"] = c.stats().snapshots;
    j["rtt_ms"] = c.rtt_ms();
    j["reconnects"] = c.stats().reconnects;
    j["late_inputs"] = c.stats().late_inputs;
    j["replayed_ticks"] = c.stats().replayed_ticks;
    j["skipped_replays"] = c.stats().skipped_replays;
    j["reused_car_steps"] = c.stats().reused_car_steps;
    j["down_bytes_per_s"] = static_cast<double>(totals.bytes_received) / wall_s;
    j["up_bytes_per_s"] = static_cast<double>(totals.bytes_sent) / wall_s;
    j["closed"] = c.close_reason();
    std::printf("%s\n", j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
    return finished;
}

}  // namespace jetrace::bot
