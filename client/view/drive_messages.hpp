// The one message a page may send to a driving jetrace-view (untrusted):
// the keyboard state, one JSON object per WebSocket text message:
//   {"type":"keys","up":B,"left":B,"right":B,"brake":B}
// every key present and a boolean, no other key, at most
// kMaxPageMessageBytes. Anything else is malformed and the caller closes
// that page's socket.
#pragma once

#include <string>
#include <string_view>

namespace jetrace::view {

struct KeysMessage {
    /// Full throttle.
    bool up = false;
    bool left = false;
    bool right = false;
    bool brake = false;
    bool operator==(const KeysMessage&) const = default;
};

/// False with a reason if `text` is not exactly a keys message.
bool parse_keys_message(std::string_view text, KeysMessage& out, std::string& error);

}  // namespace jetrace::view
