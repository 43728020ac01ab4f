#include "jetrace/client/track_download.hpp"

#include "jetrace/core/world.hpp"
#include "jetrace/tracks/jtrack.hpp"

#include <algorithm>

namespace jetrace::client {

bool TrackDownload::fail(std::string& error, std::string why) {
    active_ = false;
    bytes_.clear();
    bytes_.shrink_to_fit();
    error = std::move(why);
    return false;
}

bool TrackDownload::start(std::uint32_t size, std::uint64_t identity, std::uint32_t max_bytes, std::string& error) {
    *this = TrackDownload{};
    if (size == 0) return fail(error, "the server has no track file to download");
    if (size > max_bytes || size > proto::kMaxTrackBytes) {
        return fail(error, "the server's track file (" + std::to_string(size) + " bytes) is over our cap of " +
                               std::to_string(std::min(max_bytes, proto::kMaxTrackBytes)) + " bytes");
    }
    active_ = true;
    size_ = size;
    identity_ = identity;
    bytes_.reserve(size);
    return true;
}

bool TrackDownload::next_request(std::uint32_t& offset) {
    const std::uint64_t in_flight = requested_ - received_;
    if (!active_ || requested_ >= size_ || in_flight >= std::uint64_t{kWindowChunks} * proto::kTrackChunkBytes) {
        return false;
    }
    offset = requested_;
    requested_ += static_cast<std::uint32_t>(std::min<std::uint64_t>(proto::kTrackChunkBytes, size_ - requested_));
    return true;
}

bool TrackDownload::add(const proto::TrackChunk& chunk, std::string& error) {
    if (!active_) return fail(error, "a track chunk that was not asked for");
    if (chunk.offset != received_ || chunk.offset >= requested_) {
        return fail(error, "track chunk out of order: at byte " + std::to_string(chunk.offset) + ", expected " +
                               std::to_string(received_));
    }
    const std::uint64_t want = std::min<std::uint64_t>(proto::kTrackChunkBytes, size_ - received_);
    if (chunk.bytes.size() != want) {
        return fail(error, "track chunk at byte " + std::to_string(chunk.offset) + " has " +
                               std::to_string(chunk.bytes.size()) + " bytes, expected " + std::to_string(want));
    }
    bytes_.insert(bytes_.end(), chunk.bytes.begin(), chunk.bytes.end());
    received_ += static_cast<std::uint32_t>(want);
    return true;
}

bool TrackDownload::finish(Track& out, std::string& error) {
    if (!complete()) return fail(error, "the track file is incomplete");
    std::string why;
    Track t;
    if (!decode_jtrack(bytes_, t, why)) return fail(error, "the server's track file does not read: " + why);
    if (t.identity() != identity_) {
        return fail(error, "the server's track file is another track (identity " + hash_hex(t.identity()) + ", not " +
                               hash_hex(identity_) + ")");
    }
    out = std::move(t);
    active_ = false;
    bytes_.clear();
    bytes_.shrink_to_fit();
    return true;
}

}  // namespace jetrace::client
