#include "page_messages.hpp"

#include <nlohmann/json.hpp>

#include <cmath>

namespace jetrace::view {

namespace {

using nlohmann::json;

bool only_keys(const json& j, std::initializer_list<const char*> keys, std::string& error) {
    for (const auto& item : j.items()) {
        bool known = false;
        for (const char* want : keys) known = known || item.key() == want;
        if (!known) {
            error = "unknown key";
            return false;
        }
    }
    return true;
}

bool parse_speed(const json& j, PageMessage& out, std::string& error) {
    if (!only_keys(j, {"type", "value"}, error)) return false;
    const auto it = j.find("value");
    if (it == j.end() || !it->is_number()) {
        error = "speed: 'value' must be a number";
        return false;
    }
    const double v = it->get<double>();
    if (!std::isfinite(v) || v < kMinSpeed || v > kMaxSpeed) {
        error = "speed: 'value' must be in [0.25, 8]";
        return false;
    }
    out = SpeedMessage{v};
    return true;
}

bool parse_seek(const json& j, const PageLimits& limits, PageMessage& out, std::string& error) {
    if (!only_keys(j, {"type", "tick"}, error)) return false;
    const auto it = j.find("tick");
    if (it == j.end() || !(it->is_number_unsigned() || it->is_number_integer())) {
        error = "seek: 'tick' must be an integer";
        return false;
    }
    const bool in_range = it->is_number_unsigned() && it->get<std::uint64_t>() >= limits.first_tick &&
                          it->get<std::uint64_t>() <= limits.last_tick;
    if (!in_range) {
        error = "seek: 'tick' must be in [" + std::to_string(limits.first_tick) + ", " +
                std::to_string(limits.last_tick) + "]";
        return false;
    }
    out = SeekMessage{static_cast<std::uint32_t>(it->get<std::uint64_t>())};
    return true;
}

}  // namespace

bool parse_page_message(std::string_view text, const PageLimits& limits, PageMessage& out, std::string& error) {
    if (text.size() > kMaxPageMessageBytes) {
        error = "message longer than " + std::to_string(kMaxPageMessageBytes) + " bytes";
        return false;
    }
    const json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) {
        error = "not a JSON object";
        return false;
    }
    const auto type = j.find("type");
    if (type == j.end() || !type->is_string()) {
        error = "no string 'type'";
        return false;
    }
    const std::string& t = type->get_ref<const std::string&>();
    if (t == "play" || t == "pause") {
        if (!only_keys(j, {"type"}, error)) return false;
        out = PlayMessage{t == "play"};
        return true;
    }
    if (t == "speed") return parse_speed(j, out, error);
    if (t == "seek") return parse_seek(j, limits, out, error);
    error = "unknown type";
    return false;
}

}  // namespace jetrace::view
