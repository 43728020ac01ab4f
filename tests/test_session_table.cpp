// SessionTable: connections, slots, the reconnect grace and tokens.
#include "jetrace/server/session_table.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

using jetrace::server::Client;
using jetrace::server::ReconnectToken;
using jetrace::server::SessionTable;

namespace {

ReconnectToken token_of(std::uint8_t b) {
    ReconnectToken t{};
    t.fill(b);
    return t;
}

// A greeted player of `peer` seated in `slot`.
Client& join(SessionTable& table, jetrace::net::PeerId peer, int slot, std::uint8_t token_byte) {
    Client& c = table.connect(peer, 0);
    c.greeted = true;
    c.slot = slot;
    c.reconnect_token = token_of(token_byte);
    table.seat(c);
    return c;
}

}  // namespace

TEST(SessionTable, SeatsPlayersInTheLowestFreeSlots) {
    SessionTable table(3);
    EXPECT_EQ(table.first_free_slot(), 0);
    join(table, 7, 0, 1);
    join(table, 9, 1, 2);
    EXPECT_EQ(table.first_free_slot(), 2);
    join(table, 4, 2, 3);
    EXPECT_EQ(table.first_free_slot(), -1);
    ASSERT_NE(table.driver_of(1), nullptr);
    EXPECT_EQ(table.driver_of(1)->peer, 9u);
    EXPECT_EQ(table.players(), 3);
    // Peers come back in peer order, whatever the join order.
    EXPECT_EQ(table.player_peers(), (std::vector<jetrace::net::PeerId>{4, 7, 9}));
    table.take(9);
    table.free_slot(1);
    EXPECT_EQ(table.first_free_slot(), 1);
    EXPECT_EQ(table.driver_of(1), nullptr);
    EXPECT_EQ(table.find(9), nullptr);
}

TEST(SessionTable, ReportsConnectionsSilentPastTheHelloTimeout) {
    SessionTable table(2);
    table.connect(1, 1000);
    table.connect(2, 5000).greeted = true;
    table.connect(3, 4000);
    EXPECT_TRUE(table.silent(4000, 3000).empty());
    EXPECT_EQ(table.silent(4001, 3000), (std::vector<jetrace::net::PeerId>{1}));
    EXPECT_EQ(table.silent(9000, 3000), (std::vector<jetrace::net::PeerId>{1, 3}));
}

TEST(SessionTable, HoldsADroppedPlayersSlotUntilItsGraceEnds) {
    SessionTable table(2);
    join(table, 5, 1, 42);
    table.hold(table.take(5), 10'000);
    // Held: owned (not free) but nobody drives it.
    EXPECT_EQ(table.first_free_slot(), 0);
    EXPECT_EQ(table.driver_of(1), nullptr);
    ASSERT_NE(table.owner_of(1), nullptr);
    EXPECT_EQ(table.owner_of(1)->peer, 5u);
    Client out;
    EXPECT_FALSE(table.take_expired(9'999, out));
    EXPECT_TRUE(table.take_expired(10'000, out));
    EXPECT_EQ(out.slot, 1);
    EXPECT_TRUE(table.held().empty());
}

TEST(SessionTable, FindsATokensOwnerHeldOrLive) {
    SessionTable table(3);
    join(table, 1, 0, 11);
    join(table, 2, 1, 22);
    table.hold(table.take(2), 1'000'000);
    const ReconnectToken held = token_of(22);
    const SessionTable::TokenOwner h = table.owner_of_token(held);
    ASSERT_NE(h.client, nullptr);
    EXPECT_EQ(h.held_slot, 1);
    EXPECT_EQ(h.live_peer, SessionTable::kNoPeer);
    const ReconnectToken live = token_of(11);
    const SessionTable::TokenOwner l = table.owner_of_token(live);
    ASSERT_NE(l.client, nullptr);
    EXPECT_EQ(l.held_slot, -1);
    EXPECT_EQ(l.live_peer, 1u);
    const ReconnectToken unknown = token_of(99);
    EXPECT_EQ(table.owner_of_token(unknown).client, nullptr);
    // Taking the owner removes it from where it was.
    EXPECT_EQ(table.take(h).slot, 1);
    EXPECT_TRUE(table.held().empty());
    EXPECT_EQ(table.take(l).peer, 1u);
    EXPECT_EQ(table.find(1), nullptr);
}

TEST(SessionTable, RemembersWhyTheLatestSpentTokensAreVoid) {
    SessionTable table(1);
    const ReconnectToken first = token_of(0);
    table.retire(first, "race over");
    EXPECT_EQ(table.retired_reason(first), "race over");
    const ReconnectToken never = token_of(0xEE);
    EXPECT_EQ(table.retired_reason(never), "");
    // A bounded memory: the oldest is forgotten once 256 more are spent.
    for (int i = 1; i <= 256; ++i) {
        ReconnectToken t{};
        t[0] = static_cast<std::uint8_t>(i & 0xFF);
        t[1] = static_cast<std::uint8_t>(i >> 8);
        t[2] = 1;
        table.retire(t, "spent " + std::to_string(i));
    }
    EXPECT_EQ(table.retired_reason(first), "");
}

TEST(SessionTable, ObserversHoldNoSlotAndNoToken) {
    SessionTable table(2);
    join(table, 3, 0, 1);
    Client& eye = table.connect(5, 0);
    eye.greeted = true;
    eye.observer = true;  // no slot, and its (all-zero) token is no credential
    EXPECT_EQ(table.players(), 1);
    EXPECT_EQ(table.observers(), 1);
    EXPECT_EQ(table.player_peers(), (std::vector<jetrace::net::PeerId>{3}));
    EXPECT_EQ(table.first_free_slot(), 1);
    const ReconnectToken zeros{};
    EXPECT_EQ(table.owner_of_token(zeros).client, nullptr);
}
