// The results file of a race, and the --nonce-file table.
#include "jetrace/server/host_files.hpp"
#include "jetrace/server/path_template.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

namespace jetrace::server {

namespace {

constexpr const char* kNonceHeader = "jetrace-nonces 1";

nlohmann::json utc_or_null(std::int64_t unix_s) {
    return unix_s > 0 ? nlohmann::json(utc_iso8601(unix_s)) : nlohmann::json(nullptr);
}

bool parse_hex(const std::string& text, auth::Nonce& out) {
    if (text.size() != out.size() * 2) return false;
    for (std::size_t i = 0; i < out.size(); ++i) {
        unsigned v = 0;
        for (std::size_t k = 0; k < 2; ++k) {
            const char c = text[2 * i + k];
            const int d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
            if (d < 0) return false;
            v = v * 16 + static_cast<unsigned>(d);
        }
        out[i] = static_cast<std::uint8_t>(v);
    }
    return true;
}

}  // namespace

nlohmann::json results_json(const RaceEnd& end, const std::string& track, int laps) {
    using replay::EndReason;
    nlohmann::json j;
    j["race"] = end.race_number;
    j["track"] = track;
    j["laps"] = laps;
    j["ticks"] = end.ticks;
    j["state_hash"] = hash_hex(end.state_hash);
    j["end_reason"] = replay::end_reason_name(end.reason);
    j["aborted"] = end.reason == EndReason::aborted || end.reason == EndReason::drained;
    j["start_utc"] = utc_or_null(end.start_unix_s);
    j["end_utc"] = utc_or_null(end.end_unix_s);
    j["standings"] = nlohmann::json::array();
    std::set<std::uint8_t> listed;
    const auto dropped = [&](std::uint8_t slot) {
        for (const Racer& r : end.racers) {
            if (r.slot == slot) return r.dropped;
        }
        return false;
    };
    int pos = 1;
    for (const auto& s : end.standings) {
        listed.insert(s.slot);
        j["standings"].push_back({{"position", pos++}, {"slot", s.slot}, {"name", s.name}, {"finished", s.finished},
                                  {"lap", s.lap}, {"time_s", s.finish_time_s}, {"dropped", dropped(s.slot)}});
    }
    // Racers whose car was removed (dropped past the reconnect grace).
    for (const Racer& r : end.racers) {
        if (listed.contains(r.slot)) continue;
        j["standings"].push_back({{"position", pos++}, {"slot", r.slot}, {"name", r.name}, {"finished", false},
                                  {"lap", 0}, {"time_s", 0.0}, {"dropped", true}});
    }
    return j;
}

bool write_results(const std::string& pattern, const RaceEnd& end, const std::string& track, int laps,
                   std::string& error) {
    const std::string path = expand_path(pattern, end.race_number, end.start_unix_s);
    const std::string text = results_json(end, track, laps).dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
    if (write_file_atomically(path, text + "\n", error)) return true;
    error = "race " + std::to_string(end.race_number) + "'s results are lost: " + error;
    if (!path_varies(pattern) && std::rename(path.c_str(), (path + ".stale").c_str()) == 0) {
        error += "; the earlier results there were moved to '" + path + ".stale'";
    }
    return false;
}

bool load_nonce_file(const std::string& path, std::vector<auth::SpentNonce>& out, std::string& error) {
    out.clear();
    std::ifstream in(path);
    if (!in) {
        if (errno == ENOENT) return true;  // nothing spent yet
        error = "cannot read nonce file '" + path + "': " + std::strerror(errno);
        return false;
    }
    std::string line;
    if (!std::getline(in, line) || line != kNonceHeader) {
        error = "nonce file '" + path + "' is corrupt: it does not start with '" + kNonceHeader + "'";
        return false;
    }
    for (int n = 2; std::getline(in, line); ++n) {
        std::istringstream ls(line);
        std::string hex, extra;
        auth::SpentNonce s;
        if (!(ls >> hex >> s.expires_unix_s) || (ls >> extra) || !parse_hex(hex, s.nonce)) {
            error = "nonce file '" + path + "' is corrupt at line " + std::to_string(n) +
                    ": expected 32 lowercase hex digits and an expiry";
            return false;
        }
        out.push_back(s);
    }
    if (in.bad()) {
        error = "cannot read nonce file '" + path + "': " + std::strerror(errno);
        return false;
    }
    return true;
}

bool save_nonce_file(const std::string& path, const std::vector<auth::SpentNonce>& nonces, std::string& error) {
    std::string text = std::string(kNonceHeader) + "\n";
    for (const auth::SpentNonce& s : nonces) {
        char hex[3];
        for (std::uint8_t b : s.nonce) {
            std::snprintf(hex, sizeof hex, "%02x", b);
            text += hex;
        }
        text += " " + std::to_string(s.expires_unix_s) + "\n";
    }
    return write_file_atomically(path, text, error);
}

}  // namespace jetrace::server
