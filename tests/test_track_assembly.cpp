// TrackDownload on its own (no network): the chunks a server sends for a
// compiled track assemble into that track; a chunk of the wrong length, out
// of order or unasked for, a file over the cap or of another track is
// refused with its reason.
#include "jetrace/client/track_download.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/jtrack.hpp"

#include <gtest/gtest.h>

namespace {

namespace jp = jetrace::proto;
using jetrace::client::TrackDownload;

std::vector<std::uint8_t> ring_file() {
    jetrace::Track ring;
    jetrace::make_builtin_track("ring", ring);
    return jetrace::encode_jtrack(ring);
}

jp::TrackChunk chunk_of(const std::vector<std::uint8_t>& file, std::uint32_t offset) {
    const std::size_t n = std::min(jp::kTrackChunkBytes, file.size() - offset);
    return {offset, std::vector<std::uint8_t>(file.begin() + offset, file.begin() + static_cast<std::ptrdiff_t>(offset + n))};
}

}  // namespace

TEST(TrackAssembly, TheServersChunksGiveItsTrack) {
    const auto file = ring_file();
    jetrace::Track ring;
    jetrace::make_builtin_track("ring", ring);
    TrackDownload d;
    std::string error;
    ASSERT_TRUE(d.start(static_cast<std::uint32_t>(file.size()), ring.identity(), jp::kMaxTrackBytes, error)) << error;
    std::vector<std::uint32_t> asked;
    std::uint32_t offset = 0;
    while (d.next_request(offset)) asked.push_back(offset);
    ASSERT_EQ(asked.size(), (file.size() + jp::kTrackChunkBytes - 1) / jp::kTrackChunkBytes);  // 3 < the window
    for (std::uint32_t at : asked) ASSERT_TRUE(d.add(chunk_of(file, at), error)) << error;
    ASSERT_TRUE(d.complete());
    jetrace::Track got;
    ASSERT_TRUE(d.finish(got, error)) << error;
    EXPECT_EQ(got.identity(), ring.identity());
    EXPECT_FALSE(d.active());
}

TEST(TrackAssembly, RefusesWhatTheServerWouldNotSend) {
    const auto file = ring_file();
    const auto size = static_cast<std::uint32_t>(file.size());
    std::string error;
    TrackDownload d;
    EXPECT_FALSE(d.start(size, 1, 1000, error));
    EXPECT_NE(error.find("over our cap"), std::string::npos) << error;
    EXPECT_FALSE(d.start(0, 1, 1000, error));
    std::uint32_t offset = 0;
    const auto started = [&] {
        EXPECT_TRUE(d.start(size, 1, jp::kMaxTrackBytes, error)) << error;
        while (d.next_request(offset)) {
        }
    };
    started();
    EXPECT_FALSE(d.add(chunk_of(file, jp::kTrackChunkBytes), error));  // skips the first
    EXPECT_NE(error.find("out of order"), std::string::npos) << error;
    EXPECT_FALSE(d.active());
    started();
    jp::TrackChunk short_one = chunk_of(file, 0);
    short_one.bytes.pop_back();
    EXPECT_FALSE(d.add(short_one, error));
    EXPECT_NE(error.find("expected"), std::string::npos) << error;
    started();
    for (std::uint32_t at = 0; at < size; at += jp::kTrackChunkBytes) ASSERT_TRUE(d.add(chunk_of(file, at), error));
    EXPECT_FALSE(d.add(chunk_of(file, 0), error)) << "a chunk after the last";
    started();
    for (std::uint32_t at = 0; at < size; at += jp::kTrackChunkBytes) ASSERT_TRUE(d.add(chunk_of(file, at), error));
    jetrace::Track got;
    EXPECT_FALSE(d.finish(got, error)) << "identity 1 is no track's";
    EXPECT_NE(error.find("another track"), std::string::npos) << error;
    TrackDownload idle;
    EXPECT_FALSE(idle.add(chunk_of(file, 0), error));
    EXPECT_NE(error.find("not asked for"), std::string::npos) << error;
}
