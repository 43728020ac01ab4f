// CloseCode names (docs/PROTOCOL.md, "Close codes").
#include "jetrace/proto/close_code.hpp"

namespace jetrace::proto {

std::string_view close_code_name(std::uint16_t code) {
    switch (static_cast<CloseCode>(code)) {
        case CloseCode::unspecified: return "unspecified";
        case CloseCode::left: return "left";
        case CloseCode::server_shutdown: return "server_shutdown";
        case CloseCode::replaced: return "replaced";
        case CloseCode::lobby_cancelled: return "lobby_cancelled";
        case CloseCode::local_left: return "local_left";
        case CloseCode::local_incompatible: return "local_incompatible";
        case CloseCode::local_no_welcome: return "local_no_welcome";
        case CloseCode::local_connection_lost: return "local_connection_lost";
        case CloseCode::local_bad_track: return "local_bad_track";
        case CloseCode::refused_version: return "refused_version";
        case CloseCode::refused_token: return "refused_token";
        case CloseCode::refused_clock: return "refused_clock";
        case CloseCode::refused_full: return "refused_full";
        case CloseCode::refused_reconnect: return "refused_reconnect";
        case CloseCode::refused_draining: return "refused_draining";
        case CloseCode::refused_unallocated: return "refused_unallocated";
        case CloseCode::refused_observers_full: return "refused_observers_full";
        case CloseCode::refused_pre_hello_cap: return "refused_pre_hello_cap";
        case CloseCode::no_hello: return "no_hello";
        case CloseCode::malformed: return "malformed";
        case CloseCode::protocol_violation: return "protocol_violation";
        case CloseCode::send_queue_full: return "send_queue_full";
    }
    return "";
}

}  // namespace jetrace::proto
