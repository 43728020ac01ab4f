// Private races over loopback: a server with a connect key admits players
// whose connect token it verifies and refuses the others with the reason.
#include "jetrace/auth/connect_token.hpp"
#include "support/live_race.hpp"

namespace {

using jetrace::client::ClientState;
using jetrace::test::Bot;
using jetrace::test::kUnixNow;
using jetrace::test::LiveRace;
using jetrace::test::refusal;
namespace auth = jetrace::auth;

struct PrivateRace {
    auth::KeyPair key = auth::generate_key_pair();
    LiveRace r{jetrace::test::lobby_options([this](jetrace::server::ServerConfig& cfg) {
        cfg.connect_key = key.public_key;
        cfg.race_id = "cup";
        cfg.min_players = 1;
    })};
    std::vector<std::uint8_t> token(const std::string& name, std::int64_t valid_for_s = 60,
                                    const std::string& race = "cup") const {
        return auth::issue_connect_token(key.secret_key, name, kUnixNow + valid_for_s, race);
    }
};

jetrace::proto::Hello hello(const std::string& name, std::vector<std::uint8_t> connect_token) {
    jetrace::proto::Hello h;
    h.name = name;
    h.connect_token = std::move(connect_token);
    return h;
}

}  // namespace

TEST(PrivateRace, AdmitsAGoodTokenOnceAndRefusesTheRestWithTheReason) {
    PrivateRace p;
    LiveRace& r = p.r;
    ASSERT_TRUE(r.ok()) << r.error;
    jetrace::client::ClientConfig cc;
    cc.name = "alice";
    cc.connect_token = p.token("alice");
    Bot& alice = r.add_bot(cc);
    ASSERT_TRUE(r.run_until([&] { return alice.client->state() == ClientState::racing; }, 5000))
        << alice.client->close_reason();

    const auto other_key = auth::generate_key_pair();
    EXPECT_EQ(refusal(r.handshake(hello("bob", {}))), "private race: a connect token is required");
    EXPECT_EQ(refusal(r.handshake(
                  hello("bob", auth::issue_connect_token(other_key.secret_key, "bob", kUnixNow + 60, "cup")))),
              "connect token not signed with this server's key");
    EXPECT_EQ(refusal(r.handshake(hello("bob", p.token("bob", -30)))), "connect token expired 30 s ago");
    EXPECT_EQ(refusal(r.handshake(hello("alice", cc.connect_token))), "connect token already used");
    EXPECT_EQ(refusal(r.handshake(hello("mallory", p.token("bob")))),
              "connect token was issued to 'bob', not to 'mallory'");
    EXPECT_EQ(refusal(r.handshake(hello("bob", p.token("bob", 60, "")))),
              "connect token is for race '', this server hosts 'cup'");
    std::vector<std::uint8_t> cut = p.token("bob");
    cut.pop_back();
    EXPECT_EQ(refusal(r.handshake(hello("bob", cut))), "connect token malformed: truncated in the signature");

    // The client library reports the refusal as its close reason.
    jetrace::client::ClientConfig late;
    late.name = "carol";
    late.connect_token = p.token("carol", -1);
    Bot& carol = r.add_bot(late);
    ASSERT_TRUE(r.run_until([&] { return carol.client->state() == ClientState::closed; }, 3000));
    EXPECT_EQ(carol.client->close_reason(), "refused: connect token expired 1 s ago");
    EXPECT_EQ(carol.client->close_code(), static_cast<std::uint16_t>(jetrace::proto::CloseCode::refused_token));

    // A good token for another player still gets in.
    const auto bob = r.handshake(hello("bob", p.token("bob")));
    EXPECT_EQ(bob.index(), 1u) << refusal(bob);
}

TEST(PrivateRace, ADroppedPlayerReconnectsWithoutANewConnectToken) {
    // Its connect token is spent; the reconnect token is the proof.
    PrivateRace p;
    LiveRace& r = p.r;
    ASSERT_TRUE(r.ok()) << r.error;
    jetrace::client::ClientConfig cc;
    cc.name = "alice";
    cc.connect_token = p.token("alice");
    Bot& alice = r.add_bot(cc);
    ASSERT_TRUE(r.run_until([&] { return alice.client->state() == ClientState::racing; }, 5000));
    const int slot = alice.client->slot();
    alice.link->sever();
    ASSERT_TRUE(r.run_until([&] { return alice.client->stats().reconnects == 1 && alice.client->state() == ClientState::racing; },
                            5000))
        << alice.client->close_reason();
    EXPECT_EQ(alice.client->slot(), slot);
}

TEST(PrivateRace, NoWallClockNoAdmission) {
    PrivateRace p;
    ASSERT_TRUE(p.r.ok()) << p.r.error;
    p.r.unix_s = -1;  // the caller never passes the wall clock
    EXPECT_EQ(refusal(p.r.handshake(hello("alice", p.token("alice")))),
              "server clock not set: cannot check connect tokens");
}
