// jetrace::ops without the network: the sidecar's JSON (untrusted), the
// allocation annotations, --metrics parsing, and the Prometheus text.
#include "jetrace/ops/gameserver.hpp"
#include "jetrace/ops/metrics.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace jetrace::ops;

TEST(GameServerJson, ReadsAWatchLineAndAGetBody) {
    const std::string gs =
        R"({"object_meta":{"name":"gs","annotations":{"jetrace.dev/laps":"2","x":"y"}},"status":{"state":"Allocated"}})";
    for (const std::string& text : {gs, R"({"result":)" + gs + "}"}) {
        const auto v = parse_gameserver(text);
        ASSERT_TRUE(v) << text;
        EXPECT_EQ(v->state, "Allocated");
        EXPECT_EQ(v->annotations.at("jetrace.dev/laps"), "2");
        EXPECT_EQ(v->annotations.size(), 2u);
    }
}

TEST(GameServerJson, ToleratesMissingAndOddFields) {
    const auto v = parse_gameserver(R"({"result":{"status":{}}})");
    ASSERT_TRUE(v);
    EXPECT_EQ(v->state, "");
    EXPECT_TRUE(v->annotations.empty());
    const auto odd = parse_gameserver(
        R"({"result":{"object_meta":{"annotations":{"a":1,"b":null,"c":"ok"}},"status":{"state":7}}})");
    ASSERT_TRUE(odd);
    EXPECT_EQ(odd->state, "");
    EXPECT_EQ(odd->annotations.size(), 1u);
    EXPECT_EQ(odd->annotations.at("c"), "ok");
}

TEST(GameServerJson, RejectsWhatIsNoGameServer) {
    for (const char* text : {"", "garbage", "{", "[1,2]", "\"Allocated\"", "{\"result\":", R"({"error":{"code":14}})",
                             R"({"result":null})", R"({"result":[]})", "{\"result\":{\"status\":{\"state\":\"Allo"}) {
        EXPECT_FALSE(parse_gameserver(text)) << text;
    }
}

TEST(Allocation, ReadsEveryKey) {
    AllocationOptions a;
    std::string error;
    ASSERT_TRUE(parse_allocation({{"jetrace.dev/track", "ring"},
                                  {"jetrace.dev/laps", "5"},
                                  {"jetrace.dev/min-players", "2"},
                                  {"jetrace.dev/race-id", "cup"},
                                  {"other.io/key", "ignored"}},
                                 a, error))
        << error;
    EXPECT_EQ(a.track, "ring");
    EXPECT_EQ(a.laps, 5);
    EXPECT_EQ(a.min_players, 2);
    EXPECT_EQ(a.race_id, "cup");
    ASSERT_TRUE(parse_allocation({}, a, error));
    EXPECT_FALSE(a.laps || a.track || a.min_players || a.race_id);
}

TEST(Allocation, RefusesBadValuesNamingTheKey) {
    const std::pair<const char*, const char*> bad[] = {
        {"jetrace.dev/laps", "0"},        {"jetrace.dev/laps", "1001"},     {"jetrace.dev/laps", "-1"},
        {"jetrace.dev/laps", "+3"},       {"jetrace.dev/laps", " 3"},       {"jetrace.dev/laps", "3 laps"},
        {"jetrace.dev/laps", ""},         {"jetrace.dev/laps", "99999999"}, {"jetrace.dev/min-players", "65"},
        {"jetrace.dev/min-players", "x"}, {"jetrace.dev/track", ""},        {"jetrace.dev/lap", "3"},
    };
    for (const auto& [key, value] : bad) {
        AllocationOptions a;
        std::string error;
        EXPECT_FALSE(parse_allocation({{key, value}}, a, error)) << key << "=" << value;
        EXPECT_NE(error.find(key), std::string::npos) << error;
    }
    AllocationOptions a;
    std::string error;
    EXPECT_FALSE(parse_allocation({{"jetrace.dev/race-id", std::string(65, 'x')}}, a, error));
}

TEST(HostPort, ParsesTheForms) {
    std::string host, error;
    int port = -1;
    ASSERT_TRUE(parse_host_port("9100", host, port, error));
    EXPECT_EQ(host, "127.0.0.1");
    EXPECT_EQ(port, 9100);
    ASSERT_TRUE(parse_host_port("0.0.0.0:0", host, port, error));
    EXPECT_EQ(host, "0.0.0.0");
    EXPECT_EQ(port, 0);
    ASSERT_TRUE(parse_host_port("[::1]:80", host, port, error));
    EXPECT_EQ(host, "::1");
    for (const char* bad : {"", ":", "host:", ":80", "65536", "-1", "80x", "a:b", "host:99999"}) {
        EXPECT_FALSE(parse_host_port(bad, host, port, error)) << bad;
    }
}

TEST(Metrics, RendersThePublishedSample) {
    Metrics m;
    MetricsSample s;
    s.phase = "racing";
    s.race_number = 3;
    s.players.push_back({0, "alice", true, false, 2, false});
    s.players.push_back({1, "bob", true, true, 0, false});
    s.players.push_back({2, "carol", false, false, 1, false});
    s.counters.races_finished = 2;
    s.counters.refused[static_cast<std::size_t>(jetrace::server::Refusal::full)] = 4;
    s.refused_unallocated = 1;
    s.observers = 5;
    s.traffic.bytes_sent = 1234;
    m.observe_ticks(0.0003, 10);
    m.publish(s);
    s.counters.races_finished = 3;  // counters advance to the newest total
    m.publish(s);
    const std::string text = m.metrics_text();
    for (const char* line : {"jetrace_players 2\n", "jetrace_spectators 1\n", "jetrace_observers 5\n", "jetrace_players_held 1\n",
                             "jetrace_races_finished_total 3\n", "jetrace_network_bytes_sent_total 1234\n",
                             "jetrace_connections_refused_total{reason=\"full\"} 4\n",
                             "jetrace_connections_refused_total{reason=\"unallocated\"} 1\n",
                             "jetrace_tick_duration_seconds_count 10\n",
                             "jetrace_tick_duration_seconds_bucket{le=\"0.0005\"} 10\n",
                             "jetrace_tick_duration_seconds_bucket{le=\"0.00025\"} 0\n",
                             "# TYPE jetrace_tick_duration_seconds histogram\n",
                             "# TYPE jetrace_races_finished_total counter\n"}) {
        EXPECT_NE(text.find(line), std::string::npos) << line << "\n" << text;
    }
    const std::string status = m.status_json();
    EXPECT_NE(status.find("\"phase\":\"racing\""), std::string::npos) << status;
    EXPECT_NE(status.find("\"name\":\"alice\""), std::string::npos) << status;
    EXPECT_NE(status.find("\"lap\":2"), std::string::npos) << status;
}

TEST(Metrics, StatusSurvivesInvalidUtf8) {
    Metrics m;
    MetricsSample s;
    s.players.push_back({0, std::string("bad\xff\xfe"), true, false, 0, false});
    m.publish(s);
    EXPECT_NE(m.status_json().find("\"players\""), std::string::npos);
}
