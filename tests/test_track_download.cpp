// The track download against a live server (real ENet on 127.0.0.1,
// virtual clock): a server racing on an OBJ track no client has; a bot that
// knows only the built-in tracks fetches the server's .jtrack file with
// TrackRequests, checks it and races on it. A chunk corrupted, out of order
// or a file over the client's cap closes the client with local_bad_track;
// a request beyond the file gets the requester dropped.
#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/track_io.hpp"
#include "support/forwarding_transport.hpp"
#include "support/live_race.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {

using jetrace::test::LiveRace;
using jetrace::test::LiveRaceOptions;
namespace jp = jetrace::proto;

// A small oval that is no built-in track, written as OBJ and loaded back as
// jetrace-server --track FILE.obj would.
jetrace::Track obj_track() {
    jetrace::OvalParams p = jetrace::ring_params();
    p.name = "oval";
    p.straight_m = 140;
    const jetrace::Track made = jetrace::make_oval(p);
    const auto path = std::filesystem::temp_directory_path() / ("jetrace_download_" + std::to_string(::getpid()) + ".obj");
    std::ofstream(path) << jetrace::export_obj(made);
    jetrace::Track t;
    std::string error;
    EXPECT_TRUE(jetrace::load_track(path.string(), t, error)) << error;
    std::filesystem::remove(path);
    return t;
}

// The built-in tracks: all a client without --track knows.
struct BuiltIns {
    jetrace::Scene ring = jetrace::Scene::make(jetrace::make_oval(jetrace::ring_params()), jetrace::PhysicsSettings{});
    jetrace::Scene stadium =
        jetrace::Scene::make(jetrace::make_oval(jetrace::stadium_params()), jetrace::PhysicsSettings{});
    jetrace::client::KnownScenes known() const { return {&ring, &stadium}; }
};

// Tampers with the TrackChunks the client receives.
class ChunkTamper final : public jetrace::test::ForwardingTransport {
public:
    enum class Mode { corrupt, reorder };
    ChunkTamper(std::unique_ptr<jetrace::net::Transport> t, Mode mode) : ForwardingTransport(std::move(t)), mode_(mode) {}
    void service(std::uint64_t now_ms, std::vector<jetrace::net::Event>& events) override {
        ForwardingTransport::service(now_ms, events);
        for (jetrace::net::Event& e : events) {
            jp::Message m;
            std::string why;
            if (e.type != jetrace::net::Event::Type::received || !jp::decode(e.data, m, why)) continue;
            auto* chunk = std::get_if<jp::TrackChunk>(&m);
            if (chunk == nullptr || chunk->offset != jp::kTrackChunkBytes) continue;
            if (mode_ == Mode::corrupt) chunk->bytes[chunk->bytes.size() / 2] ^= 0x40;
            else chunk->offset += 1;
            e.data = jp::encode(m);
            ++tampered;
        }
    }
    int tampered = 0;

private:
    Mode mode_;
};

LiveRaceOptions obj_race(const jetrace::Track* track) {
    LiveRaceOptions o;
    o.bots = 0;
    o.max_players = 4;
    o.min_players = 1;
    o.track = track;
    return o;
}

}  // namespace

TEST(TrackDownload, ABotWithoutTheTrackRacesTheServersObjTrack) {
    const jetrace::Track track = obj_track();
    const BuiltIns builtins;
    ASSERT_NE(track.identity(), builtins.ring.track.identity());
    LiveRace race(obj_race(&track));
    ASSERT_TRUE(race.ok()) << race.error;
    const std::vector<std::uint8_t>& file = race.server().track_file();
    ASSERT_GT(file.size(), 2 * jp::kTrackChunkBytes) << "a track of a few chunks at least";
    jetrace::client::ClientConfig cc;
    cc.name = "newcomer";
    race.add_bot(cc, builtins.known());
    ASSERT_TRUE(race.run()) << "the race did not end in time";
    ASSERT_EQ(race.ends.size(), 1u);
    const auto& bot = *race.bot(0).client;
    EXPECT_EQ(bot.scene().track.identity(), track.identity()) << "the bot races on another track";
    EXPECT_TRUE(race.finished(0)) << "the bot did not finish: " << bot.close_reason();
    EXPECT_EQ(jetrace::hash_hex(bot.results().state_hash), jetrace::hash_hex(race.ends.front().state_hash));
    EXPECT_FALSE(bot.downloading_track());
}

TEST(TrackDownload, ABadChunkOrAnOversizedFileClosesTheClient) {
    const jetrace::Track track = obj_track();
    const BuiltIns builtins;
    LiveRaceOptions o = obj_race(&track);
    o.min_players = 4;  // no race: the lobby waits while the clients fail
    LiveRace race(o);
    ASSERT_TRUE(race.ok()) << race.error;
    ChunkTamper* corrupt = nullptr;
    ChunkTamper* reorder = nullptr;
    jetrace::client::ClientConfig cc;
    cc.name = "corrupted";
    auto& a = race.add_bot(cc, builtins.known(), [&](std::unique_ptr<jetrace::net::Transport> t) {
        auto w = std::make_unique<ChunkTamper>(std::move(t), ChunkTamper::Mode::corrupt);
        corrupt = w.get();
        return w;
    });
    cc.name = "reordered";
    auto& b = race.add_bot(cc, builtins.known(), [&](std::unique_ptr<jetrace::net::Transport> t) {
        auto w = std::make_unique<ChunkTamper>(std::move(t), ChunkTamper::Mode::reorder);
        reorder = w.get();
        return w;
    });
    cc.name = "small cap";
    cc.max_track_bytes = 1000;
    auto& c = race.add_bot(cc, builtins.known());
    jetrace::test::RawClient& greedy = race.add_raw();
    greedy.send_on_connect(jp::Hello{jp::kProtocolVersion, "greedy", {}, {}});
    bool asked = false;
    const auto closed = [](const jetrace::test::Bot& bot) {
        return bot.client->state() == jetrace::client::ClientState::closed;
    };
    race.run_until(
        [&] {
            if (greedy.welcome && !asked) {
                greedy.send(jp::TrackRequest{greedy.welcome->track_bytes});
                asked = true;
            }
            return closed(a) && closed(b) && closed(c) && !greedy.goodbye.empty();
        },
        20000);
    const auto bad_track = static_cast<std::uint16_t>(jp::CloseCode::local_bad_track);
    for (const auto* bot : {&a, &b, &c}) {
        EXPECT_TRUE(closed(*bot)) << bot->client->close_reason();
        EXPECT_EQ(bot->client->close_code(), bad_track) << bot->client->close_reason();
    }
    ASSERT_NE(corrupt, nullptr);
    ASSERT_NE(reorder, nullptr);
    EXPECT_EQ(corrupt->tampered, 1);
    EXPECT_EQ(reorder->tampered, 1);
    EXPECT_NE(a.client->close_reason().find("does not read"), std::string::npos) << a.client->close_reason();
    EXPECT_NE(b.client->close_reason().find("out of order"), std::string::npos) << b.client->close_reason();
    EXPECT_NE(c.client->close_reason().find("over our cap"), std::string::npos) << c.client->close_reason();
    EXPECT_NE(greedy.goodbye.find("protocol violation: track request at byte"), std::string::npos) << greedy.goodbye;
}
