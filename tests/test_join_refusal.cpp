// A server's pre-Hello cap refuses a connection request with close code 2008
// (refused_pre_hello_cap) as the data of an ENet disconnect. Over scripted
// transports (no network, no clock): the client tries again within its join
// window, each refusal in a row doubling the pause (up to 4 times), spread
// at random so that clients refused together come back apart, and once
// it gives up it closes with that code and says why; jetrace-bot reports the
// bot as refused, with its name, the code and what to do. jetrace-bot opens
// at most --join-limit connections per server address at a time.
#include "bot_report.hpp"
#include "join_pacing.hpp"

#include "jetrace/client/race_client.hpp"
#include "jetrace/net/transport.hpp"
#include "jetrace/proto/close_code.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "support/scripted_transport.hpp"
#include "support/welcome.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace jetrace;
using client::ClientState;

constexpr std::uint16_t kCap = static_cast<std::uint16_t>(proto::CloseCode::refused_pre_hello_cap);

const Scene& ring() {
    static const Scene s = Scene::make(make_oval(ring_params()), PhysicsSettings{});
    return s;
}

Input no_input(const Scene&, const WorldState&, int) { return Input{}; }

// A client whose Connector hands out scripted transports, and its clock.
struct Joiner {
    std::vector<test::ScriptedTransport*> opened;
    std::unique_ptr<client::RaceClient> client;
    std::uint64_t now_us = 0;

    explicit Joiner(const client::ClientConfig& cc) {
        client = std::make_unique<client::RaceClient>(cc, ring(), [this]() -> std::unique_ptr<net::Transport> {
            auto t = std::make_unique<test::ScriptedTransport>();
            opened.push_back(t.get());
            return t;
        });
    }
    test::ScriptedTransport& last() { return *opened.back(); }
    void run_for(double seconds) {
        for (const std::uint64_t end = now_us + static_cast<std::uint64_t>(seconds * 1e6); now_us < end;) {
            now_us += 10000;
            client->update(now_us, no_input);
        }
    }
    /// The newest attempt is refused by the cap; returns how long until the
    /// next one opens (unit: s, to 10 ms; 0: none within 10 s).
    double refused_then_wait() {
        const std::size_t before = opened.size();
        last().drop(0, kCap);
        for (int i = 1; i <= 1000; ++i) {
            run_for(0.01);
            if (opened.size() > before) return i * 0.01;
        }
        return 0;
    }
};

client::ClientConfig config(double join_window_s) {
    client::ClientConfig cc;
    cc.name = "bot7";
    cc.join_window_s = join_window_s;
    cc.reconnect_retry_s = 0.5;
    return cc;
}

TEST(JoinRefusal, TheCapsRefusalIsTriedAgainWithABackOff) {
    Joiner j(config(20.0));
    ASSERT_EQ(j.opened.size(), 1u);
    // 0.5 s, then doubled for each refusal in a row, up to 2 s; each spread
    // over 0.5 to 1.5 times (the wait is measured to the next 10 ms).
    for (const double pause : {0.5, 1.0, 2.0, 2.0}) {
        const double waited = j.refused_then_wait();
        EXPECT_GE(waited, 0.5 * pause) << "after " << j.opened.size() << " attempts";
        EXPECT_LE(waited, 1.5 * pause + 0.03) << "after " << j.opened.size() << " attempts";
        EXPECT_EQ(j.client->state(), ClientState::reconnecting);
    }
    // The fifth attempt gets in: a plain join.
    j.last().connect();
    j.run_for(0.05);
    EXPECT_EQ(j.client->state(), ClientState::waiting_welcome);
    j.last().deliver(0, net::Channel::reliable, proto::encode(test::welcome_for(ring(), 3)));
    j.run_for(0.05);
    EXPECT_EQ(j.client->state(), ClientState::in_lobby);
    EXPECT_EQ(j.client->slot(), 3);
    EXPECT_EQ(j.client->close_code(), 0u);
}

TEST(JoinRefusal, ClientsRefusedTogetherComeBackApart) {
    double first = 10, last = 0;
    for (int i = 0; i < 16; ++i) {
        Joiner j(config(20.0));
        const double waited = j.refused_then_wait();
        EXPECT_GE(waited, 0.25);
        EXPECT_LE(waited, 0.78);
        first = std::min(first, waited);
        last = std::max(last, waited);
    }
    EXPECT_GT(last - first, 0.1) << "16 clients refused at once all came back within 0.1 s";
}

TEST(JoinRefusal, AFailureOtherThanTheCapDoesNotBackOff) {
    Joiner j(config(20.0));
    EXPECT_GT(j.refused_then_wait(), 0.0);
    EXPECT_GT(j.refused_then_wait(), 0.0);
    const std::size_t before = j.opened.size();
    j.last().drop();  // no code: nobody answered
    j.run_for(0.51);
    EXPECT_EQ(j.opened.size(), before + 1) << "a timeout is retried at the plain pause";
}

TEST(JoinRefusal, GivingUpClosesWithTheCapsCode) {
    {
        Joiner j(config(3.0));
        for (int i = 0; i < 20 && j.client->state() != ClientState::closed; ++i) j.refused_then_wait();
        ASSERT_EQ(j.client->state(), ClientState::closed);
        EXPECT_EQ(j.client->close_code(), kCap);
        const std::string& why = j.client->close_reason();
        EXPECT_EQ(why.rfind("refused: too many connections from this address are waiting for their Hello", 0), 0u)
            << why;
        EXPECT_NE(why.find("could not join within 3"), std::string::npos) << why;
    }
    {
        Joiner j(config(0.0));  // no join window: the first refusal is final
        j.last().drop(0, kCap);
        j.run_for(1.0);
        ASSERT_EQ(j.client->state(), ClientState::closed);
        EXPECT_EQ(j.client->close_code(), kCap);
        EXPECT_EQ(j.opened.size(), 1u);
    }
}

TEST(JoinRefusal, OnlyAnAttemptThatNeverCameUpIsACapRefusal) {
    for (const bool came_up : {false, true}) {
        Joiner j(config(0.0));
        if (came_up) {
            j.last().connect();
            j.run_for(0.05);
            ASSERT_EQ(j.client->state(), ClientState::waiting_welcome);
        }
        j.last().drop(0, came_up ? kCap : 0);
        j.run_for(0.1);
        ASSERT_EQ(j.client->state(), ClientState::closed);
        EXPECT_EQ(j.client->close_reason(), "disconnected");
        EXPECT_EQ(j.client->close_code(), static_cast<std::uint16_t>(proto::CloseCode::local_connection_lost));
    }
}

TEST(JoinRefusal, TheBotSaysItWasRefusedAndWhy) {
    Joiner j(config(0.0));
    j.last().drop(0, kCap);
    j.run_for(0.1);
    ASSERT_EQ(j.client->state(), ClientState::closed);
    const bot::ExitCode outcome = bot::outcome_of(*j.client, false, false);
    EXPECT_EQ(outcome, bot::kRefused);
    EXPECT_STREQ(bot::outcome_name(outcome), "refused");
    const std::string line = bot::give_up_line("bot7", outcome, j.client->close_code(), j.client->close_reason());
    EXPECT_EQ(line.rfind("jetrace-bot: bot7: refused: too many connections from this address", 0), 0u) << line;
    EXPECT_NE(line.find("[refused_pre_hello_cap 2008]"), std::string::npos) << line;
    EXPECT_NE(line.find("--pre-hello-limit"), std::string::npos) << line;

    const std::string lost = bot::give_up_line("bot8", bot::kLostConnection, 3003, "disconnected");
    EXPECT_EQ(lost.rfind("jetrace-bot: bot8: disconnected [local_connection_lost 3003]: no server answered", 0), 0u)
        << lost;
    EXPECT_EQ(bot::give_up_line("bot9", bot::kFinished, 3000, "done racing"), "");
    EXPECT_EQ(bot::give_up_line("bot9", bot::kStopped, 3000, "bot stopped by a signal"), "");
}

TEST(JoinPacing, AtMostTheLimitOfOneAddressJoinAtATime) {
    using bot::JoinPhase;
    const std::vector<std::size_t> address = {0, 1, 0, 1, 0, 1, 0, 1, 0, 1};
    std::vector<JoinPhase> phase(address.size(), JoinPhase::waiting);
    std::vector<std::size_t> start = bot::bots_to_start(phase, address, 2, 2);
    EXPECT_EQ(start, (std::vector<std::size_t>{0, 1, 2, 3}));
    for (const std::size_t i : start) phase[i] = JoinPhase::joining;
    EXPECT_TRUE(bot::bots_to_start(phase, address, 2, 2).empty()) << "both addresses are at their limit";
    phase[2] = JoinPhase::through;  // welcomed
    EXPECT_EQ(bot::bots_to_start(phase, address, 2, 2), (std::vector<std::size_t>{4}));
    phase[4] = JoinPhase::joining;
    phase[0] = JoinPhase::through;  // gave up
    phase[1] = JoinPhase::through;
    phase[3] = JoinPhase::through;
    // Address 0 has one joining (4): one more (6); address 1 none: two (5, 7).
    EXPECT_EQ(bot::bots_to_start(phase, address, 2, 2), (std::vector<std::size_t>{5, 6, 7}));
    EXPECT_EQ(bot::bots_to_start(phase, address, 2, 64).size(), 5u) << "every waiting bot within a large limit";
}

}  // namespace
