// The client's track download (TrackDownload) fed TrackChunk messages from
// untrusted bytes. Input: the announced file size (u32 little-endian), a
// flags byte (bit 0: expect the identity of whatever the accepted chunks
// assemble to, so that a whole valid file is accepted; else an identity no
// track has), then records of a u16 little-endian length and that many bytes
// of a message, decoded as the client decodes (proto::decode) and given to
// the download when it is a TrackChunk. Invariants: a refused size or chunk
// names why and ends the download; an accepted chunk is the next one in
// order with the length the server sends; the bytes received never pass the
// size; a finished download is the expected track or a named refusal.
#include "fuzz_check.hpp"
#include "jetrace/client/track_download.hpp"
#include "jetrace/tracks/jtrack.hpp"

#include <algorithm>
#include <vector>

namespace {

std::uint32_t u32_at(const std::uint8_t* p) {
    return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
}

/// The identity of the track `file` holds (0: none reads).
std::uint64_t identity_of(const std::vector<std::uint8_t>& file) {
    jetrace::Track t;
    std::string error;
    return jetrace::decode_jtrack(file, t, error) ? t.identity() : 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 5) return 0;
    const std::uint32_t announced = u32_at(data);
    const bool expect_assembled = (data[4] & 1) != 0;
    // Split the records first: the expected identity may depend on them.
    std::vector<jetrace::proto::TrackChunk> chunks;
    for (std::size_t at = 5; at + 2 <= size;) {
        const std::size_t len = std::size_t{data[at]} | std::size_t{data[at + 1]} << 8;
        at += 2;
        const std::size_t n = std::min(len, size - at);
        jetrace::proto::Message m;
        std::string error;
        if (jetrace::proto::decode(jetrace::fuzz::bytes(data + at, n), m, error)) {
            if (auto* c = std::get_if<jetrace::proto::TrackChunk>(&m)) chunks.push_back(std::move(*c));
        } else {
            JETRACE_FUZZ_CHECK(!error.empty());
        }
        at += n;
    }
    std::vector<std::uint8_t> file;
    for (const auto& c : chunks) file.insert(file.end(), c.bytes.begin(), c.bytes.end());
    const std::uint64_t identity = expect_assembled ? identity_of(file) : 0;

    jetrace::client::TrackDownload d;
    std::string error;
    if (!d.start(announced, identity, jetrace::proto::kMaxTrackBytes, error)) {
        JETRACE_FUZZ_CHECK(!error.empty() && !d.active());
        return 0;
    }
    std::uint32_t offset = 0;
    for (const auto& c : chunks) {
        while (d.next_request(offset)) JETRACE_FUZZ_CHECK(offset < d.size());
        const std::uint32_t before = d.received();
        if (!d.add(c, error)) {
            JETRACE_FUZZ_CHECK(!error.empty() && !d.active());
            return 0;
        }
        JETRACE_FUZZ_CHECK(c.offset == before && d.received() == before + c.bytes.size());
        JETRACE_FUZZ_CHECK(d.received() <= d.size());
        if (d.complete()) break;
    }
    if (!d.complete()) return 0;
    jetrace::Track track;
    if (d.finish(track, error)) {
        JETRACE_FUZZ_CHECK(track.identity() == identity && jetrace::validate(track).empty());
    } else {
        JETRACE_FUZZ_CHECK(!error.empty());
    }
    JETRACE_FUZZ_CHECK(!d.active());
    return 0;
}
