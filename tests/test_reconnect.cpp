// Reconnects over loopback with a live server: a dropped player's car waits
// for the grace period and its reconnect token; nobody else can take it.
#include "support/live_race.hpp"

namespace {

using jetrace::client::ClientState;
using jetrace::proto::RacePhase;
using jetrace::test::Bot;
using jetrace::test::LiveRace;
using jetrace::test::lobby_options;
using jetrace::test::refusal;

jetrace::proto::Hello hello(const std::string& name, std::vector<std::uint8_t> token) {
    jetrace::proto::Hello h;
    h.name = name;
    h.reconnect_token = std::move(token);
    return h;
}

bool racing(const LiveRace& r) { return r.server().phase() == RacePhase::racing; }

}  // namespace

TEST(Reconnect, DropMidRaceGetsTheSameCarBackAndFinishes) {
    LiveRace r(lobby_options());
    ASSERT_TRUE(r.ok()) << r.error;
    Bot& a = r.add_bot("bot0");
    Bot& b = r.add_bot("bot1");
    ASSERT_TRUE(r.run_until([&] { return racing(r) && r.server().world().tick > r.server().world().start_tick + 240; },
                            20000));
    const int slot = b.client->slot();
    const auto token = b.client->reconnect_token();
    ASSERT_EQ(token.size(), jetrace::proto::kTokenBytes);
    ASSERT_TRUE(r.server().world().cars[static_cast<std::size_t>(slot)].active);

    b.link->sever();
    // Held: the car stays in the race while the bot is away (its updates
    // paused for 500 virtual ms so that the server sees it gone).
    ASSERT_TRUE(r.run_until([&] { return r.server().held_slots() == 1; }, 2000, {&b}));
    r.run_until([] { return false; }, 500, {&b});
    EXPECT_TRUE(r.server().world().cars[static_cast<std::size_t>(slot)].active) << "the held car was removed";
    EXPECT_EQ(r.server().players(), 1);

    ASSERT_TRUE(r.run_until([&] { return b.client->stats().reconnects == 1 && b.client->state() == ClientState::racing; },
                            5000));
    EXPECT_EQ(b.client->slot(), slot) << "reconnected to another slot";
    EXPECT_EQ(r.server().held_slots(), 0);
    EXPECT_NE(b.client->reconnect_token(), token) << "the reconnect token must change after use";

    ASSERT_TRUE(r.run_until([&] { return r.server().done(); }, 120000)) << "the race did not end";
    r.run_until([] { return false; }, 300);
    for (const Bot* bot : {&a, &b}) {
        const auto& res = bot->client->results();
        ASSERT_EQ(res.standings.size(), 2u);
        for (const auto& s : res.standings) EXPECT_TRUE(s.finished) << s.name << " did not finish";
    }
    bool listed = false;
    for (const auto& s : b.client->results().standings) listed = listed || (s.slot == slot && s.name == "bot1");
    EXPECT_TRUE(listed) << "bot1 is not in the standings under its slot";
    EXPECT_EQ(b.client->stats().reconnects, 1u);
    EXPECT_EQ(a.client->stats().reconnects, 0u);
}

TEST(Reconnect, WrongStolenAndSpentTokensAreRefusedAndTheSlotStaysReserved) {
    LiveRace r(lobby_options([](auto& cfg) {
        cfg.max_players = 2;
        cfg.min_players = 3;  // stays in the lobby: no race needed here
    }));
    ASSERT_TRUE(r.ok()) << r.error;
    Bot& a = r.add_bot("alice");
    ASSERT_TRUE(r.run_until([&] { return a.client->state() == ClientState::in_lobby; }, 3000));
    const auto token = a.client->reconnect_token();
    const int slot = a.client->slot();

    std::vector<std::uint8_t> wrong = token;
    wrong[0] ^= 1;
    EXPECT_EQ(refusal(r.handshake(hello("alice", wrong))), "unknown reconnect token");

    a.link->sever();
    ASSERT_TRUE(r.run_until([&] { return r.server().held_slots() == 1; }, 2000, {&a}));
    // Another name with alice's token (stolen, or a bug): refused, and the
    // token stays good for alice.
    EXPECT_EQ(refusal(r.handshake(hello("mallory", token), {&a})),
              "reconnect token belongs to another player name");
    // A newcomer without a token gets the other slot; the next one finds the
    // server full: the held slot is not given away.
    std::unique_ptr<jetrace::test::RawClient> bob_link;
    const auto bob = r.handshake(hello("bob", {}), {&a}, &bob_link);
    ASSERT_EQ(bob.index(), 1u) << refusal(bob);
    EXPECT_NE(std::get<1>(bob).slot, slot);
    EXPECT_EQ(refusal(r.handshake(hello("carol", {}), {&a})), "server full (2 players)");

    ASSERT_TRUE(r.run_until([&] { return a.client->stats().reconnects == 1 && a.client->state() == ClientState::in_lobby; },
                            5000));
    EXPECT_EQ(a.client->slot(), slot);
    EXPECT_EQ(refusal(r.handshake(hello("alice", token))), "reconnect token already used");
}

TEST(Reconnect, ALiveConnectionIsReplacedByItsOwnersReconnect) {
    // The client may notice a dead connection before the server does: its
    // reconnect replaces the old connection instead of waiting for it.
    LiveRace r(lobby_options([](auto& cfg) { cfg.min_players = 3; }));
    ASSERT_TRUE(r.ok()) << r.error;
    Bot& a = r.add_bot("alice");
    ASSERT_TRUE(r.run_until([&] { return a.client->state() == ClientState::in_lobby; }, 3000));
    const auto answer = r.handshake(hello("alice", a.client->reconnect_token()));
    ASSERT_EQ(answer.index(), 1u) << refusal(answer);
    EXPECT_EQ(std::get<1>(answer).slot, a.client->slot());
    ASSERT_TRUE(r.run_until([&] { return a.client->state() == ClientState::closed; }, 3000));
    EXPECT_EQ(a.client->close_reason(), "server: replaced by a reconnection of the same player");
    EXPECT_EQ(a.client->close_code(), static_cast<std::uint16_t>(jetrace::proto::CloseCode::replaced));
}

TEST(Reconnect, AfterTheGraceTheCarIsRemovedAndTheTokenExpired) {
    LiveRace r(lobby_options([](auto& cfg) { cfg.reconnect_grace_s = 2.0; }));
    ASSERT_TRUE(r.ok()) << r.error;
    r.add_bot("bot0");
    jetrace::client::ClientConfig cc;
    cc.name = "bot1";
    cc.reconnect_window_s = 0;  // gives up at once
    Bot& b = r.add_bot(cc);
    ASSERT_TRUE(r.run_until([&] { return racing(r); }, 20000));
    const auto slot = static_cast<std::size_t>(b.client->slot());
    const auto token = b.client->reconnect_token();
    b.link->sever();
    ASSERT_TRUE(r.run_until([&] { return r.server().held_slots() == 1; }, 2000));
    EXPECT_EQ(b.client->state(), ClientState::closed);
    const std::uint64_t held_at = r.now_us();
    ASSERT_TRUE(r.run_until([&] { return !r.server().world().cars[slot].active; }, 5000));
    const double held_s = static_cast<double>(r.now_us() - held_at) / 1e6;
    EXPECT_GT(held_s, 1.9) << "removed before the grace period was over";
    EXPECT_LT(held_s, 2.1);
    EXPECT_EQ(r.server().held_slots(), 0);
    EXPECT_EQ(refusal(r.handshake(hello("bot1", token))), "reconnect token expired: the grace period is over");
    EXPECT_TRUE(racing(r)) << "the race goes on with bot0";
}

TEST(Reconnect, AGoodbyeCannotBeTakenBack) {
    LiveRace r(lobby_options([](auto& cfg) { cfg.min_players = 3; }));
    ASSERT_TRUE(r.ok()) << r.error;
    Bot& a = r.add_bot("alice");
    ASSERT_TRUE(r.run_until([&] { return a.client->state() == ClientState::in_lobby; }, 3000));
    const auto token = a.client->reconnect_token();
    a.client->leave("done");
    // The token is void from the Goodbye on, whether or not the server has
    // seen the connection close yet.
    r.run_until([] { return false; }, 200);
    EXPECT_EQ(refusal(r.handshake(hello("alice", token))),
              "reconnect token no longer valid: the player said goodbye");
    EXPECT_EQ(r.server().held_slots(), 0);
}
