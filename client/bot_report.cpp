// jetrace-bot's outcomes and JSON lines.
#include "bot_report.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <string>
#include <string_view>

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

namespace {

/// What a bot that gave up with `close_code` can do about it ("": nothing to say).
const char* give_up_hint(std::uint16_t close_code) {
    switch (static_cast<proto::CloseCode>(close_code)) {
        case proto::CloseCode::refused_pre_hello_cap:
            return "keep --join-limit at most the server's --pre-hello-limit, or run fewer clients from this address "
                   "at once";
        case proto::CloseCode::local_connection_lost:
            return "no server answered at that address, or the connection dropped for good";
        case proto::CloseCode::local_no_welcome: return "the server never answered the Hello";
        default: return "";
    }
}

}  // namespace

std::string give_up_line(const std::string& name, ExitCode code, std::uint16_t close_code,
                         const std::string& reason) {
    if (code != kRefused && code != kLostConnection) return "";
    const std::string_view code_name = proto::close_code_name(close_code);
    std::string line = "jetrace-bot: " + name + ": " + reason + " [" +
                       (code_name.empty() ? std::string("close code") : std::string(code_name)) + " " +
                       std::to_string(close_code) + "]";
    const std::string hint = give_up_hint(close_code);
    if (!hint.empty()) line += ": " + hint;
    return line;
}

bool print_bot_line(const client::RaceClient* c, const std::string& name, bool stopped, double wall_s,
                    ExitCode& code) {
    int position = 0;
    bool finished = false;
    if (c != nullptr) {
        const auto& r = c->results();
        for (std::size_t i = 0; i < r.standings.size(); ++i) {
            if (r.standings[i].slot == c->slot() && r.standings[i].name == name) {
                position = static_cast<int>(i) + 1;
                finished = r.standings[i].finished;
            }
        }
    }
    code = c != nullptr ? outcome_of(*c, finished, stopped) : kStopped;
    const client::ClientStats stats = c != nullptr ? c->stats() : client::ClientStats{};
    const net::Totals totals = c != nullptr ? c->totals() : net::Totals{};
    nlohmann::json j;
    j["name"] = name;
    j["finished"] = finished;
    j["position"] = position;
    j["outcome"] = outcome_name(code);
    j["corrections"] = stats.corrections;
    j["corrections_late"] = stats.corrections_late;
    j["corrections_near_car"] = stats.corrections_near_car;
    j["max_correction_m"] = stats.max_correction_m;
    j["drawn_checked"] = stats.drawn_checked;
    j["drawn_off"] = stats.drawn_off;
    j["drawn_off_unexplained"] = stats.drawn_off_unexplained;
    j["snapshots"] = stats.snapshots;
    j["rtt_ms"] = c != nullptr ? c->rtt_ms() : 0.0;
    j["reconnects"] = stats.reconnects;
    j["late_inputs"] = stats.late_inputs;
    j["replayed_ticks"] = stats.replayed_ticks;
    j["skipped_replays"] = stats.skipped_replays;
    j["reused_car_steps"] = stats.reused_car_steps;
    j["down_bytes_per_s"] = static_cast<double>(totals.bytes_received) / wall_s;
    j["up_bytes_per_s"] = static_cast<double>(totals.bytes_sent) / wall_s;
    j["closed"] = c != nullptr ? c->close_reason() : std::string("stopped before it connected");
    std::printf("%s\n", j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
    return finished;
}

}  // namespace jetrace::bot
