// RaceClient's joining, over scripted transports (no network, no clock):
// the Welcome picks the track among the client's known scenes; a
// connection that never came up joins again within
// ClientConfig::join_window_s, while a drop after the Hello, a refusal or a
// missing Welcome is final.
#include "jetrace/client/race_client.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "support/scripted_transport.hpp"
#include "support/welcome.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace {

using namespace jetrace;
using client::ClientState;

// The server's end of a scripted connection, in proto messages: it delivers
// messages on the reliable channel and checks that every datagram the client
// sends decodes.
class ServerScript final : public test::ScriptedTransport {
public:
    ServerScript() {
        on_send = [](const Record& r) {
            proto::Message m;
            std::string error;
            EXPECT_TRUE(proto::decode(r.data, m, error)) << error;
        };
    }
    void deliver(const proto::Message& m) { ScriptedTransport::deliver(0, net::Channel::reliable, proto::encode(m)); }
    /// What the client sent, decoded, in order.
    std::vector<proto::Message> messages() const {
        std::vector<proto::Message> out;
        for (const Record& r : ScriptedTransport::sent()) {
            proto::Message m;
            std::string error;
            if (proto::decode(r.data, m, error)) out.push_back(std::move(m));
        }
        return out;
    }
};

struct Tracks {
    Scene stadium = Scene::make(make_oval(stadium_params()), PhysicsSettings{});
    Scene ring = Scene::make(make_oval(ring_params()), PhysicsSettings{});
};

const Tracks& tracks() {
    static const Tracks t;
    return t;
}

using test::welcome_for;

Input no_input(const Scene&, const WorldState&, int) { return Input{}; }

// A client over a Connector that hands out the transports of `script` in
// order (nullptr once they run out: "cannot connect right now").
struct Joiner {
    std::vector<ServerScript*> opened;
    std::unique_ptr<client::RaceClient> client;
    std::uint64_t now_us = 0;

    Joiner(const client::ClientConfig& cc, const client::KnownScenes& scenes, int transports) {
        auto remaining = std::make_shared<int>(transports);
        const auto open = [this, remaining]() -> std::unique_ptr<net::Transport> {
            if (*remaining == 0) return nullptr;
            --*remaining;
            auto t = std::make_unique<ServerScript>();
            opened.push_back(t.get());
            return t;
        };
        client = std::make_unique<client::RaceClient>(cc, scenes, open);
    }
    ServerScript& last() { return *opened.back(); }
    /// The newest connection comes up (the client sends its Hello).
    void come_up() {
        last().connect();
        run_for(0.1);
    }
    void run_for(double seconds) {
        for (const std::uint64_t end = now_us + static_cast<std::uint64_t>(seconds * 1e6); now_us < end;) {
            now_us += 10000;
            client->update(now_us, no_input);
        }
    }
};

TEST(ClientJoin, TheWelcomePicksTheKnownTrack) {
    for (const Scene* expected : {&tracks().stadium, &tracks().ring}) {
        ServerScript t;
        client::RaceClient c(client::ClientConfig{}, client::KnownScenes{&tracks().stadium, &tracks().ring}, t);
        t.connect();
        c.update(1000, no_input);
        ASSERT_EQ(c.state(), ClientState::waiting_welcome);
        ASSERT_EQ(t.messages().size(), 1u);
        EXPECT_TRUE(std::holds_alternative<proto::Hello>(t.messages()[0]));
        t.deliver(welcome_for(*expected, 3));
        c.update(2000, no_input);
        EXPECT_EQ(c.state(), ClientState::in_lobby);
        EXPECT_EQ(c.slot(), 3);
        EXPECT_EQ(&c.scene(), expected);
    }
}

TEST(ClientJoin, AnUnknownTrackOrOtherPhysicsLeaves) {
    Scene other = Scene::make(make_oval(ring_params()), [] {
        PhysicsSettings p;
        p.grip_mps2 *= 2.0;
        return p;
    }());
    struct Case {
        proto::Welcome welcome;
        const char* reason;
    };
    proto::Welcome unknown = welcome_for(tracks().stadium, 0);
    unknown.track_identity ^= 1;
    for (const Case& k : {Case{unknown, "track mismatch"}, Case{welcome_for(other, 0), "physics settings differ"}}) {
        ServerScript t;
        client::RaceClient c(client::ClientConfig{}, client::KnownScenes{&tracks().stadium, &tracks().ring}, t);
        t.connect();
        t.deliver(k.welcome);
        c.update(1000, no_input);
        EXPECT_EQ(c.state(), ClientState::closed);
        EXPECT_EQ(c.close_reason().rfind(k.reason, 0), 0u) << c.close_reason();
        EXPECT_EQ(c.close_code(), static_cast<std::uint16_t>(proto::CloseCode::local_incompatible));
        EXPECT_TRUE(t.disconnected());
        ASSERT_FALSE(t.messages().empty());
        EXPECT_TRUE(std::holds_alternative<proto::Goodbye>(t.messages().back()));
    }
}

TEST(ClientJoin, AdoptsTheServersPhysicsSettingsFromTheSameCore) {
    PhysicsSettings fast;
    fast.tick_rate_hz = 240;
    struct Case {
        PhysicsSettings physics;
        std::uint64_t hash;
        const char* reason;  // nullptr: adopted
    };
    for (const Case& k : {Case{fast, proto::physics_hash(fast), nullptr},
                          Case{fast, proto::physics_hash(fast) ^ 1, "physics settings differ from the server's (not the same physics core)"}}) {
        ServerScript t;
        client::RaceClient c(client::ClientConfig{}, client::KnownScenes{&tracks().ring}, t);
        t.connect();
        proto::Welcome w = welcome_for(tracks().ring, 0);
        w.tick_rate_hz = static_cast<std::uint16_t>(k.physics.tick_rate_hz);
        w.physics = k.physics;
        w.physics_hash = k.hash;
        t.deliver(w);
        c.update(1000, no_input);
        if (k.reason == nullptr) {
            EXPECT_EQ(c.state(), ClientState::in_lobby) << c.close_reason();
            EXPECT_EQ(c.scene().physics.tick_rate_hz, 240);
            EXPECT_EQ(c.scene().track.identity(), tracks().ring.track.identity());
        } else {
            EXPECT_EQ(c.state(), ClientState::closed);
            EXPECT_EQ(c.close_reason().rfind(k.reason, 0), 0u) << c.close_reason();
        }
    }
}

// Settings the core refuses do not even decode (proto::decode runs
// validate()): the client ignores that Welcome as malformed and waits on.
TEST(ClientJoin, IgnoresAWelcomeWithUnusablePhysicsSettings) {
    PhysicsSettings bad;
    bad.slide_mps2 = bad.grip_mps2 + 1;  // validate() refuses: slide must be below grip
    ServerScript t;
    client::RaceClient c(client::ClientConfig{}, client::KnownScenes{&tracks().ring}, t);
    t.connect();
    proto::Welcome w = welcome_for(tracks().ring, 0);
    w.tick_rate_hz = static_cast<std::uint16_t>(bad.tick_rate_hz);
    w.physics = bad;
    w.physics_hash = proto::physics_hash(bad);
    proto::Message m;
    std::string error;
    EXPECT_FALSE(proto::decode(proto::encode(w), m, error));
    EXPECT_NE(error.find("Welcome.physics: slide_mps2 must be in [0, grip_mps2]"), std::string::npos) << error;
    t.deliver(w);
    c.update(1000, no_input);
    EXPECT_EQ(c.state(), ClientState::waiting_welcome);
}

TEST(ClientJoin, AConnectionThatNeverCameUpJoinsAgain) {
    client::ClientConfig cc;
    cc.join_window_s = 5.0;
    cc.reconnect_retry_s = 0.5;
    Joiner j(cc, {&tracks().ring}, 3);
    ASSERT_EQ(j.opened.size(), 1u);
    // The first two attempts fail before they come up (no server yet).
    j.last().drop();
    j.run_for(0.2);
    EXPECT_EQ(j.client->state(), ClientState::reconnecting);
    EXPECT_EQ(j.opened.size(), 1u) << "waits reconnect_retry_s before the next attempt";
    j.run_for(0.5);
    ASSERT_EQ(j.opened.size(), 2u);
    j.last().drop();
    j.run_for(1.0);
    ASSERT_EQ(j.opened.size(), 3u);
    j.come_up();
    EXPECT_EQ(j.client->state(), ClientState::waiting_welcome);
    const std::vector<proto::Message> sent = j.last().messages();
    ASSERT_EQ(sent.size(), 1u);
    const auto* hello = std::get_if<proto::Hello>(&sent[0]);
    ASSERT_NE(hello, nullptr);
    EXPECT_TRUE(hello->reconnect_token.empty()) << "a join, not a reconnect";
    j.last().deliver(welcome_for(tracks().ring, 1));
    j.run_for(0.1);
    EXPECT_EQ(j.client->state(), ClientState::in_lobby);
    EXPECT_EQ(j.client->slot(), 1);
    EXPECT_EQ(j.client->stats().reconnects, 0u) << "joining again is not a reconnect";
}

TEST(ClientJoin, ADropAfterTheHelloIsFinal) {
    // The server may have admitted the Hello (and spent its connect token):
    // a second Hello could take a second slot or be refused.
    for (const bool rejoined : {false, true}) {
        Joiner j(client::ClientConfig{}, {&tracks().ring}, 5);
        if (rejoined) {
            j.last().drop();
            j.run_for(1.0);
            ASSERT_EQ(j.opened.size(), 2u);
        }
        j.come_up();
        ASSERT_EQ(j.client->state(), ClientState::waiting_welcome);
        j.last().drop();
        j.run_for(2.0);
        EXPECT_EQ(j.client->state(), ClientState::closed);
        EXPECT_EQ(j.client->close_reason(), "disconnected");
        EXPECT_EQ(j.opened.size(), rejoined ? 2u : 1u);
    }
}

TEST(ClientJoin, AServerThatNeverGotTheHelloIsJoinedAgain) {
    // Its Goodbye's code says so (no_hello): it admitted nothing. Any other
    // Goodbye before the Welcome is final, whatever its text says.
    for (const bool no_hello : {true, false}) {
        Joiner j(client::ClientConfig{}, {&tracks().ring}, 5);
        j.come_up();
        ASSERT_EQ(j.client->state(), ClientState::waiting_welcome);
        const std::string reason = no_hello ? "hello lost" : std::string(proto::kNoHelloReason) + " 5.000000 s";
        const auto code = no_hello ? proto::CloseCode::no_hello : proto::CloseCode::server_shutdown;
        j.last().deliver(proto::Goodbye{reason, static_cast<std::uint16_t>(code)});
        j.last().drop();
        j.run_for(1.0);
        if (!no_hello) {
            EXPECT_EQ(j.client->state(), ClientState::closed);
            EXPECT_EQ(j.client->close_reason(), "server: " + reason);
            EXPECT_EQ(j.client->close_code(), static_cast<std::uint16_t>(proto::CloseCode::server_shutdown));
            EXPECT_EQ(j.opened.size(), 1u);
            continue;
        }
        ASSERT_EQ(j.opened.size(), 2u);
        j.come_up();
        j.last().deliver(welcome_for(tracks().ring, 2));
        j.run_for(0.1);
        EXPECT_EQ(j.client->state(), ClientState::in_lobby);
        EXPECT_EQ(j.client->close_reason(), "");
    }
}

TEST(ClientJoin, NoWelcomeWithinTheTimeoutLeaves) {
    client::ClientConfig cc;
    cc.welcome_timeout_s = 3.0;
    Joiner j(cc, {&tracks().ring}, 5);
    j.last().connect();
    j.run_for(2.9);
    EXPECT_EQ(j.client->state(), ClientState::waiting_welcome);
    j.run_for(0.2);
    EXPECT_EQ(j.client->state(), ClientState::closed);
    EXPECT_EQ(j.client->close_reason().rfind("no welcome within 3", 0), 0u) << j.client->close_reason();
    EXPECT_EQ(j.client->close_code(), static_cast<std::uint16_t>(proto::CloseCode::local_no_welcome));
    EXPECT_TRUE(j.last().disconnected());
    ASSERT_FALSE(j.last().messages().empty());
    EXPECT_TRUE(std::holds_alternative<proto::Goodbye>(j.last().messages().back()));
}

TEST(ClientJoin, JoiningGivesUpAfterTheWindow) {
    client::ClientConfig cc;
    cc.join_window_s = 2.0;
    cc.reconnect_retry_s = 0.5;
    Joiner j(cc, {&tracks().ring}, 100);
    for (int i = 0; i < 40 && j.client->state() != ClientState::closed; ++i) {
        j.last().drop();  // every attempt fails
        j.run_for(0.25);
    }
    EXPECT_EQ(j.client->state(), ClientState::closed);
    EXPECT_EQ(j.client->close_reason().rfind("disconnected: could not join within", 0), 0u) << j.client->close_reason();
    EXPECT_EQ(j.client->close_code(), static_cast<std::uint16_t>(proto::CloseCode::local_connection_lost));
    EXPECT_TRUE(j.last().disconnected()) << "the attempt under way is called off";
    // One attempt per retry interval for the 2 s window, not one per failure.
    EXPECT_GE(j.opened.size(), 3u);
    EXPECT_LE(j.opened.size(), 6u);
}

TEST(ClientJoin, ARefusalOrAZeroWindowIsFinal) {
    {
        Joiner j(client::ClientConfig{}, {&tracks().ring}, 5);
        j.last().connect();
        j.last().deliver(proto::Refuse{"server full", static_cast<std::uint16_t>(proto::CloseCode::refused_full)});
        j.last().drop();
        j.run_for(2.0);
        EXPECT_EQ(j.client->state(), ClientState::closed);
        EXPECT_EQ(j.client->close_reason(), "refused: server full");
        EXPECT_EQ(j.client->close_code(), static_cast<std::uint16_t>(proto::CloseCode::refused_full));
        EXPECT_EQ(j.opened.size(), 1u);
    }
    {
        client::ClientConfig cc;
        cc.join_window_s = 0.0;
        Joiner j(cc, {&tracks().ring}, 5);
        j.last().drop();
        j.run_for(2.0);
        EXPECT_EQ(j.client->state(), ClientState::closed);
        EXPECT_EQ(j.client->close_reason(), "disconnected");
        EXPECT_EQ(j.opened.size(), 1u);
    }
}

}  // namespace
