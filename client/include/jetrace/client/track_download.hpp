// The track download: a client whose known tracks lack the server's fetches
// the server's compiled .jtrack file (Welcome.track_bytes) with
// TrackRequests and assembles the TrackChunks, then reads the file with the
// .jtrack reader's checks and accepts it only if its identity is the one the
// Welcome named (docs/PROTOCOL.md, "Track download"). The chunks come from
// the network: every offset and length is checked, and any surprise fails
// the download with a reason, never a crash.
#pragma once

#include "jetrace/core/track.hpp"
#include "jetrace/proto/messages.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace jetrace::client {

class TrackDownload {
public:
    /// Requests in flight at most (unit: chunks).
    static constexpr std::uint32_t kWindowChunks = 4;

    /// Starts receiving a file of `size` bytes whose track must have
    /// `identity`. False with `error` if `size` is 0 or above `max_bytes`
    /// (the client's cap, unit: bytes).
    bool start(std::uint32_t size, std::uint64_t identity, std::uint32_t max_bytes, std::string& error);
    /// Receiving (started, not yet complete or failed).
    bool active() const { return active_; }
    /// The offset of the next TrackRequest to send, while fewer than
    /// kWindowChunks are in flight; false when none is due.
    bool next_request(std::uint32_t& offset);
    /// Takes a chunk. False with `error` if it is not the next one in order
    /// or its length is not what the server sends for its offset (then the
    /// download is over).
    bool add(const proto::TrackChunk& chunk, std::string& error);
    /// Every byte received.
    bool complete() const { return active_ && received_ == size_; }
    /// Reads the complete file (decode_jtrack) into `out` and checks its
    /// identity. False with `error` if it does not read or is another track.
    /// The download is over either way.
    bool finish(Track& out, std::string& error);
    std::uint32_t size() const { return size_; }
    std::uint32_t received() const { return received_; }

private:
    bool fail(std::string& error, std::string why);

    bool active_ = false;
    std::uint32_t size_ = 0;
    std::uint64_t identity_ = 0;
    std::uint32_t received_ = 0;
    std::uint32_t requested_ = 0;
    std::vector<std::uint8_t> bytes_;
};

}  // namespace jetrace::client
