#include "drive_messages.hpp"

#include "page_messages.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <utility>

namespace jetrace::view {

bool parse_keys_message(std::string_view text, KeysMessage& out, std::string& error) {
    using nlohmann::json;
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
    if (type == j.end() || !type->is_string() || type->get_ref<const std::string&>() != "keys") {
        error = "a driving page sends only {\"type\":\"keys\",...}";
        return false;
    }
    KeysMessage k;
    const std::array<std::pair<const char*, bool*>, 4> fields{
        {{"up", &k.up}, {"left", &k.left}, {"right", &k.right}, {"brake", &k.brake}}};
    if (j.size() != fields.size() + 1) {
        error = "keys: exactly 'up', 'left', 'right' and 'brake' are expected";
        return false;
    }
    for (const auto& [name, target] : fields) {
        const auto it = j.find(name);
        if (it == j.end() || !it->is_boolean()) {
            error = std::string("keys: '") + name + "' must be true or false";
            return false;
        }
        *target = it->get<bool>();
    }
    out = k;
    return true;
}

}  // namespace jetrace::view
