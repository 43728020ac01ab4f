// What every connection of one jetrace-view process shares: the loaded
// replays (read-only) or the live session, the settings, the track mesh
// bytes, page numbers.
#pragma once

#include "live_session.hpp"
#include "replay_player.hpp"
#include "view_settings.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace jetrace::view {

struct ViewContext {
    ViewSettings settings;
    std::unique_ptr<ReplayPlayer> main;
    std::vector<std::unique_ptr<ReplayPlayer>> ghosts;
    /// Live and drive modes: the race client (main is null then).
    LiveSession* live = nullptr;
    /// track_mesh_bytes() of the main replay's (or the live race's) track, served as /track.bin.
    std::string track_bin;
    /// Number of the next page (WebSocket) to connect, for log lines.
    std::uint64_t next_page = 1;
    /// Pages connected now (WsSession counts itself in and out).
    int open_pages = 0;

    std::vector<const ReplayPlayer*> ghost_players() const {
        std::vector<const ReplayPlayer*> out;
        for (const auto& g : ghosts) out.push_back(g.get());
        return out;
    }
};

}  // namespace jetrace::view
