// Agones GameServer JSON and allocation annotations.
#include "jetrace/ops/gameserver.hpp"

#include <nlohmann/json.hpp>

#include <charconv>

namespace jetrace::ops {

namespace {

// A strict decimal integer in [lo, hi]: digits only, no sign or spaces.
std::optional<int> strict_int(const std::string& s, int lo, int hi) {
    if (s.empty() || s.size() > 7) return std::nullopt;
    int v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc{} || end != s.data() + s.size() || s[0] == '-' || s[0] == '+') return std::nullopt;
    if (v < lo || v > hi) return std::nullopt;
    return v;
}

const nlohmann::json* member(const nlohmann::json& j, const char* key) {
    if (!j.is_object()) return nullptr;
    const auto it = j.find(key);
    return it == j.end() ? nullptr : &*it;
}

}  // namespace

std::optional<GameServerView> parse_gameserver(std::string_view text) {
    const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return std::nullopt;
    // A watch line wraps the GameServer in "result"; GET /gameserver does not.
    const nlohmann::json* gs = member(doc, "result");
    if (gs == nullptr) gs = &doc;
    const nlohmann::json* meta = member(*gs, "object_meta");
    const nlohmann::json* status = member(*gs, "status");
    if (meta == nullptr && status == nullptr) return std::nullopt;
    GameServerView view;
    if (status != nullptr) {
        const nlohmann::json* state = member(*status, "state");
        if (state != nullptr && state->is_string()) view.state = state->get<std::string>();
    }
    if (meta != nullptr) {
        const nlohmann::json* ann = member(*meta, "annotations");
        if (ann != nullptr && ann->is_object()) {
            for (const auto& [k, v] : ann->items()) {
                if (v.is_string()) view.annotations[k] = v.get<std::string>();
            }
        }
    }
    return view;
}

bool parse_allocation(const std::map<std::string, std::string>& annotations, AllocationOptions& out,
                      std::string& error) {
    out = AllocationOptions{};
    for (const auto& [key, value] : annotations) {
        if (key.compare(0, kAnnotationPrefix.size(), kAnnotationPrefix) != 0) continue;
        const std::string bad = "annotation " + key + "=\"" + value.substr(0, 80) + "\": ";
        if (key == kLapsAnnotation) {
            out.laps = strict_int(value, 1, 1000);
            if (!out.laps) error = bad + "laps must be an integer in [1, 1000]";
        } else if (key == kMinPlayersAnnotation) {
            out.min_players = strict_int(value, 1, 64);
            if (!out.min_players) error = bad + "min players must be an integer in [1, 64]";
        } else if (key == kTrackAnnotation || key == kRaceIdAnnotation) {
            if (value.empty() || value.size() > 64) {
                error = bad + "must be 1 to 64 bytes";
            } else {
                (key == kTrackAnnotation ? out.track : out.race_id) = value;
            }
        } else {
            error = bad + "unknown key (jetrace reads " + std::string(kTrackAnnotation) + ", " +
                    std::string(kLapsAnnotation) + ", " + std::string(kMinPlayersAnnotation) + " and " +
                    std::string(kRaceIdAnnotation) + ")";
        }
        if (!error.empty()) return false;
    }
    return true;
}

}  // namespace jetrace::ops
