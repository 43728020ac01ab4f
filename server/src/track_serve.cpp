// RaceServer: the track download: clients without the server's track fetch
// its compiled .jtrack file chunk by chunk (docs/PROTOCOL.md, "Track
// download").
#include "jetrace/server/race_server.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/jtrack.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace jetrace::server {

std::vector<std::uint8_t> track_file_of(const Track& track) {
    Track builtin;
    if (make_builtin_track(track.name, builtin) && builtin.identity() == track.identity()) return {};
    std::vector<std::uint8_t> file = encode_jtrack(track);
    if (file.size() > proto::kMaxTrackBytes) {
        spdlog::warn("track '{}': its .jtrack file ({} bytes) is over the protocol's {} bytes: clients cannot download it",
                     track.name, file.size(), proto::kMaxTrackBytes);
        return {};
    }
    return file;
}

void RaceServer::on_track_request(Client& c, const proto::TrackRequest& r) {
    if (r.offset >= track_file_.size()) {
        drop(c.peer, DropReason::protocol,
             "protocol violation: track request at byte " + std::to_string(r.offset) + " of a " +
                 std::to_string(track_file_.size()) + "-byte track file");
        return;
    }
    // Each byte twice at most (a client that starts over after a bad
    // chunk), so that requests cannot make the server send without end.
    const std::size_t n = std::min(proto::kTrackChunkBytes, track_file_.size() - r.offset);
    if (c.track_bytes_sent + n > 2 * track_file_.size()) {
        drop(c.peer, DropReason::protocol, "protocol violation: the track file requested more than twice");
        return;
    }
    c.track_bytes_sent += n;
    const auto from = track_file_.begin() + static_cast<std::ptrdiff_t>(r.offset);
    send(c.peer, net::Channel::reliable,
         proto::TrackChunk{r.offset, std::vector<std::uint8_t>(from, from + static_cast<std::ptrdiff_t>(n))});
}

}  // namespace jetrace::server
