// jetrace::proto: every message round-trips; decoding rejects malformed,
// truncated, oversized and out-of-range bytes without crashing; the world
// payload reproduces real race states bit for bit against any baseline.
#include "jetrace/builtin_tracks.hpp"
#include "jetrace/driver_ai.hpp"
#include "jetrace/offline_race.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/proto/world_codec.hpp"
#include "jetrace_generated.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <random>
#include <tuple>

namespace jp = jetrace::proto;
namespace fb = flatbuffers;
namespace w = jetrace::wire;

namespace {

// ------------------------------------------------------------ equality

auto tie(const jp::Hello& m) { return std::tie(m.protocol_version, m.name, m.reconnect_token); }
auto tie(const jp::Welcome& m) {
    return std::tie(m.protocol_version, m.slot, m.max_players, m.tick_rate_hz, m.snapshot_rate_hz, m.track_name,
                    m.track_identity, m.physics_hash, m.server_tick, m.reconnect_token);
}
auto tie(const jp::Refuse& m) { return std::tie(m.reason); }
auto tie(const jp::InputBatch& m) { return std::tie(m.first_tick, m.inputs, m.ack_snapshot_tick); }
auto tie(const jp::Snapshot& m) {
    return std::tie(m.server_tick, m.baseline_tick, m.last_applied_input_tick, m.input_margin_ticks, m.phase,
                    m.race_number, m.world);
}
auto tie(const jp::PlayerInfo& m) { return std::tie(m.slot, m.name, m.spectating); }
auto tie(const jp::StandingEntry& m) { return std::tie(m.slot, m.name, m.finished, m.lap, m.finish_time_s); }
auto tie(const jp::Goodbye& m) { return std::tie(m.reason); }

template <typename T>
bool same_list(const std::vector<T>& a, const std::vector<T>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (tie(a[i]) != tie(b[i])) return false;
    return true;
}
bool same(const jp::RaceStatus& a, const jp::RaceStatus& b) {
    return std::tie(a.phase, a.race_number, a.start_tick, a.laps) ==
               std::tie(b.phase, b.race_number, b.start_tick, b.laps) &&
           same_list(a.players, b.players);
}
bool same(const jp::Results& a, const jp::Results& b) {
    return a.race_number == b.race_number && a.state_hash == b.state_hash && same_list(a.standings, b.standings);
}
template <typename T>
bool same(const T& a, const T& b) {
    return tie(a) == tie(b);
}
bool same(const jp::Message& a, const jp::Message& b) {
    if (a.index() != b.index()) return false;
    return std::visit([&](const auto& x) { return same(x, std::get<std::decay_t<decltype(x)>>(b)); }, a);
}

std::vector<std::uint8_t> token(std::uint8_t first) {
    std::vector<std::uint8_t> t(jp::kTokenBytes);
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = static_cast<std::uint8_t>(first + i * 17);
    return t;
}

/// One of every message, with non-default values and limits.
std::vector<jp::Message> sample_messages() {
    std::vector<jp::Message> out;
    out.push_back(jp::Hello{1, "Ayrton", {}});
    out.push_back(jp::Hello{7, "\xc3\xa9t\xc3\xa9 \xe2\x9c\x93 1234567890123456789012", token(3)});  // 32 bytes
    out.push_back(jp::Hello{0, "", {}});
    out.push_back(jp::Welcome{1, 5, 8, 120, 60, "ring", 0x1234567890abcdefull, 0xfedcba0987654321ull, 99, token(9)});
    out.push_back(jp::Welcome{2, 63, 64, 10000, 1, std::string(256, 't'), 0, 0, 0xFFFFFFFFu, {}});
    out.push_back(jp::Refuse{"server full"});
    out.push_back(jp::Refuse{std::string(256, 'r')});
    jp::InputBatch batch{1000, {}, 998};
    for (int i = 0; i < 64; ++i) batch.inputs.push_back(jetrace::Input::clamped(i % 16, i % 31 - 15, i % 2));
    out.push_back(batch);
    out.push_back(jp::InputBatch{0xFFFFFFFFu, {jetrace::Input::clamped(15, -15, 1)}, jp::kNoTick});
    out.push_back(jp::Snapshot{5000, 4996, 5003, -3, jp::RacePhase::racing, 2, {1, 2, 3, 255}});
    out.push_back(jp::Snapshot{7, jp::kNoTick, jp::kNoTick, 32767, jp::RacePhase::finished, 0, {0}});
    jp::RaceStatus status{jp::RacePhase::countdown, 3, 12345, 5, {}};
    for (std::uint8_t s = 0; s < 64; ++s) status.players.push_back({static_cast<std::uint8_t>(63 - s), "p", s % 3 == 0});
    out.push_back(status);
    out.push_back(jp::RaceStatus{jp::RacePhase::lobby, 0, 0, 1, {}});
    jp::Results results{4, {}, 0xabcdef0123456789ull};
    results.standings.push_back({2, "winner", true, 3, 61.25});
    results.standings.push_back({0, "second", true, 3, 62.0078125});
    results.standings.push_back({1, "dnf", false, 1, 0.0});
    out.push_back(results);
    out.push_back(jp::Goodbye{"bye"});
    out.push_back(jp::Goodbye{""});
    return out;
}

std::uint64_t test_seed() {
    const char* env = std::getenv("JETRACE_TEST_SEED");
    const std::uint64_t seed = env ? std::strtoull(env, nullptr, 0) : 20240521u;
    std::cout << "[ seed ] JETRACE_TEST_SEED=" << seed << "\n";
    return seed;
}

bool decodes(std::span<const std::uint8_t> bytes, std::string* why = nullptr) {
    jp::Message m;
    std::string error;
    const bool ok = jp::decode(bytes, m, error);
    if (!ok && why) *why = error;
    return ok;
}

/// Finishes a hand-built envelope (to build messages encode() refuses to).
std::vector<std::uint8_t> finish(fb::FlatBufferBuilder& b, w::Body type, fb::Offset<void> body) {
    w::FinishEnvelopeBuffer(b, w::CreateEnvelope(b, type, body));
    return {b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize()};
}

}  // namespace

// ================================================================ messages

TEST(ProtoMessages, EveryMessageRoundTrips) {
    for (const jp::Message& m : sample_messages()) {
        const std::vector<std::uint8_t> bytes = jp::encode(m);
        ASSERT_LE(bytes.size(), jp::kMaxMessageBytes);
        jp::Message back;
        std::string error;
        ASSERT_TRUE(jp::decode(bytes, back, error)) << "message " << m.index() << ": " << error;
        EXPECT_TRUE(same(m, back)) << "message " << m.index();
    }
}

TEST(ProtoMessages, DecodesFromUnalignedMemory) {
    for (const jp::Message& m : sample_messages()) {
        const std::vector<std::uint8_t> bytes = jp::encode(m);
        std::vector<std::uint8_t> shifted(bytes.size() + 1);
        std::copy(bytes.begin(), bytes.end(), shifted.begin() + 1);
        jp::Message back;
        std::string error;
        ASSERT_TRUE(jp::decode(std::span(shifted).subspan(1), back, error)) << error;
        EXPECT_TRUE(same(m, back));
    }
}

TEST(ProtoMessages, RejectsEmptyOversizedAndWrongIdentifier) {
    std::string why;
    EXPECT_FALSE(decodes({}, &why));
    EXPECT_NE(why.find("empty"), std::string::npos);
    std::vector<std::uint8_t> big = jp::encode(jp::Goodbye{"x"});
    big.resize(jp::kMaxMessageBytes + 1);
    EXPECT_FALSE(decodes(big, &why));
    std::vector<std::uint8_t> bytes = jp::encode(jp::Hello{1, "a", {}});
    bytes[4] = 'X';
    EXPECT_FALSE(decodes(bytes, &why));
    EXPECT_NE(why.find("identifier"), std::string::npos) << why;
}

TEST(ProtoMessages, RejectsEveryTruncation) {
    for (const jp::Message& m : sample_messages()) {
        const std::vector<std::uint8_t> bytes = jp::encode(m);
        for (std::size_t len = 0; len < bytes.size(); ++len)
            EXPECT_FALSE(decodes(std::span(bytes).first(len))) << "message " << m.index() << " cut to " << len;
    }
}

TEST(ProtoMessages, RandomBytesNeverCrash) {
    std::mt19937_64 rng(test_seed());
    const auto samples = sample_messages();
    int accepted = 0;
    for (int i = 0; i < 10000; ++i) {
        std::vector<std::uint8_t> buf;
        if (i % 3 == 0) {
            // Pure noise, often with the right identifier to reach the verifier.
            buf.resize(1 + rng() % 300);
            for (auto& b : buf) b = static_cast<std::uint8_t>(rng());
            if (buf.size() >= 8 && (rng() & 1)) std::copy_n("JTR1", 4, buf.begin() + 4);
        } else {
            // A valid message with a few bytes changed.
            buf = jp::encode(samples[rng() % samples.size()]);
            const int flips = 1 + static_cast<int>(rng() % 4);
            for (int f = 0; f < flips; ++f) buf[rng() % buf.size()] = static_cast<std::uint8_t>(rng());
        }
        accepted += decodes(buf) ? 1 : 0;  // must simply not crash
    }
    std::cout << "[ info ] mutated/random messages accepted: " << accepted << " of 10000\n";
}

TEST(ProtoMessages, RejectsOutOfRangeFields) {
    std::string why;
    auto rejects = [&](const std::vector<std::uint8_t>& bytes, const char* field) {
        const bool ok = decodes(bytes, &why);
        EXPECT_FALSE(ok) << field;
        EXPECT_NE(why.find(field), std::string::npos) << "error '" << why << "' does not name " << field;
    };
    auto hello = [](const std::string& name, std::vector<std::uint8_t> tok) {
        fb::FlatBufferBuilder b;
        auto n = b.CreateString(name);
        auto t = b.CreateVector(tok);
        return finish(b, w::Body_Hello, w::CreateHello(b, 1, n, t).Union());
    };
    rejects(hello(std::string(33, 'n'), {}), "Hello.name");
    rejects(hello("bad\x01", {}), "Hello.name");
    rejects(hello("bad\xff", {}), "Hello.name");
    rejects(hello("\xc0\xaf", {}), "Hello.name");  // overlong '/'
    rejects(hello("ok", std::vector<std::uint8_t>(5, 1)), "Hello.reconnect_token");
    {  // Hello without its required name
        fb::FlatBufferBuilder b;
        const auto start = b.StartTable();
        b.AddElement<std::uint16_t>(w::Hello::VT_PROTOCOL_VERSION, 1, 0);
        const fb::Offset<void> body(b.EndTable(start));
        EXPECT_FALSE(decodes(finish(b, w::Body_Hello, body), &why));
    }
    auto batch = [](std::vector<std::uint16_t> inputs, std::uint32_t first = 0) {
        fb::FlatBufferBuilder b;
        auto v = b.CreateVector(inputs);
        return finish(b, w::Body_InputBatch, w::CreateInputBatch(b, first, v, 0).Union());
    };
    rejects(batch(std::vector<std::uint16_t>(65, 0)), "InputBatch.inputs");
    rejects(batch({}), "InputBatch.inputs");
    rejects(batch({1, 1024}), "InputBatch.inputs");
    rejects(batch({1, 2}, 0xFFFFFFFFu), "InputBatch.first_tick");
    EXPECT_TRUE(decodes(batch({1023})));
    auto welcome = [](std::uint8_t slot, std::uint8_t max, std::uint16_t rate, std::uint16_t snap) {
        fb::FlatBufferBuilder b;
        auto name = b.CreateString("ring");
        return finish(b, w::Body_Welcome,
                      w::CreateWelcome(b, 1, slot, max, rate, snap, name, 0, 0, 0, 0).Union());
    };
    rejects(welcome(64, 64, 120, 60), "Welcome.slot");
    rejects(welcome(0, 65, 120, 60), "Welcome.max_players");
    rejects(welcome(0, 0, 120, 60), "Welcome.max_players");
    rejects(welcome(0, 8, 0, 60), "Welcome.tick_rate_hz");
    rejects(welcome(0, 8, 120, 10001), "Welcome.snapshot_rate_hz");
    auto snapshot = [](std::uint8_t phase, std::uint32_t tick, std::uint32_t base) {
        fb::FlatBufferBuilder b;
        auto world = b.CreateVector(std::vector<std::uint8_t>{1});
        return finish(b, w::Body_Snapshot,
                      w::CreateSnapshot(b, tick, base, 0, 0, static_cast<w::RacePhase>(phase), 0, world).Union());
    };
    rejects(snapshot(4, 10, 5), "Snapshot.phase");
    rejects(snapshot(255, 10, 5), "Snapshot.phase");
    rejects(snapshot(2, 10, 11), "Snapshot.baseline_tick");
    auto status = [](std::vector<std::uint8_t> slots, std::uint8_t spectating = 0) {
        fb::FlatBufferBuilder b;
        std::vector<fb::Offset<w::PlayerInfo>> players;
        for (std::uint8_t s : slots) {
            auto name = b.CreateString("p");
            const auto start = b.StartTable();
            b.AddOffset(w::PlayerInfo::VT_NAME, name);
            b.AddElement<std::uint8_t>(w::PlayerInfo::VT_SLOT, s, 0);
            b.AddElement<std::uint8_t>(w::PlayerInfo::VT_SPECTATING, spectating, 0);
            players.push_back(fb::Offset<w::PlayerInfo>(b.EndTable(start)));
        }
        auto list = b.CreateVector(players);
        return finish(b, w::Body_RaceStatus, w::CreateRaceStatus(b, w::RacePhase_Racing, 1, 0, 3, list).Union());
    };
    rejects(status({0, 64}), "RaceStatus.players[1].slot");
    rejects(status({3, 3}), "RaceStatus.players[1].slot");
    rejects(status({1}, 2), "RaceStatus.players[0].spectating");
    std::vector<std::uint8_t> many(65);
    for (std::size_t i = 0; i < many.size(); ++i) many[i] = static_cast<std::uint8_t>(i);
    rejects(status(many), "RaceStatus.players");
    auto results = [](double time) {
        fb::FlatBufferBuilder b;
        auto e = w::CreateStandingEntry(b, 0, b.CreateString("x"), true, 1, time);
        auto list = b.CreateVector(std::vector<fb::Offset<w::StandingEntry>>{e});
        return finish(b, w::Body_Results, w::CreateResults(b, 1, list, 0).Union());
    };
    rejects(results(std::numeric_limits<double>::quiet_NaN()), "finish_time_s");
    rejects(results(std::numeric_limits<double>::infinity()), "finish_time_s");
    rejects(results(-1.0), "finish_time_s");
    EXPECT_TRUE(decodes(results(12.5)));
    {  // unknown union member, and no body at all
        fb::FlatBufferBuilder b;
        auto r = w::CreateGoodbye(b, b.CreateString("x"));
        rejects(finish(b, static_cast<w::Body>(9), r.Union()), "Envelope.body_type");
        fb::FlatBufferBuilder b2;
        auto r2 = w::CreateGoodbye(b2, b2.CreateString("x"));
        rejects(finish(b2, w::Body_NONE, r2.Union()), "Envelope.body_type");
    }
    {  // a long reason
        fb::FlatBufferBuilder b;
        auto r = w::CreateRefuse(b, b.CreateString(std::string(257, 'x')));
        rejects(finish(b, w::Body_Refuse, r.Union()), "Refuse.reason");
    }
}

TEST(ProtoMessages, PhysicsHashCoversEveryField) {
    // A new field in PhysicsSettings changes its size: add it to the hash
    // (jetrace::physics_fingerprint, which jp::physics_hash is) and below.
    EXPECT_EQ(sizeof(jetrace::PhysicsSettings), 128u) << "PhysicsSettings changed: update the physics hash";
    const jetrace::PhysicsSettings base;
    const std::uint64_t h = jp::physics_hash(base);
    EXPECT_EQ(h, jp::physics_hash(jetrace::PhysicsSettings{}));
    using S = jetrace::PhysicsSettings;
    const std::vector<void (*)(S&)> mutations = {
        [](S& s) { s.tick_rate_hz = 60; }, [](S& s) { s.gravity_mps2 = std::nextafter(s.gravity_mps2, 10.0); },
        [](S& s) { s.car_radius_m = 2.0; }, [](S& s) { s.thrust_mps2 = 20.0; },
        [](S& s) { s.drag_per_m = 1e-4; }, [](S& s) { s.brake_mps2 = 20.0; },
        [](S& s) { s.steer_rate_radps = 1.0; }, [](S& s) { s.grip_mps2 = 30.0; },
        [](S& s) { s.slide_mps2 = 10.0; }, [](S& s) { s.align_rate_per_s = 10.0; },
        [](S& s) { s.ride_min_cos = 0.4; }, [](S& s) { s.no_progress_s = 5.0; },
        [](S& s) { s.resolver_passes = 10; }, [](S& s) { s.resolver_epsilon_m = 1e-3; },
        [](S& s) { s.contact_skin_m = 0.1; }, [](S& s) { s.integrator = jetrace::Integrator::explicit_euler; },
        [](S& s) { s.quantize_state = false; }};
    for (std::size_t i = 0; i < mutations.size(); ++i) {
        S s = base;
        mutations[i](s);
        EXPECT_NE(jp::physics_hash(s), h) << "field " << i;
    }
}

TEST(ProtoMessages, PhaseNames) {
    EXPECT_STREQ(jp::to_string(jp::RacePhase::lobby), "lobby");
    EXPECT_STREQ(jp::to_string(jp::RacePhase::countdown), "countdown");
    EXPECT_STREQ(jp::to_string(jp::RacePhase::racing), "racing");
    EXPECT_STREQ(jp::to_string(jp::RacePhase::finished), "finished");
}

// ================================================================ world payload

namespace {

/// An 8-car AI race on `ring`: the snapshot of every tick, with the inputs
/// that produced it. Car 7 leaves at tick 500 and rejoins at tick 700.
struct Race {
    jetrace::Scene scene;
    std::vector<jp::WorldSnapshot> history;
};

const Race& ring_race() {
    static const Race* race = [] {
        jetrace::Track track;
        EXPECT_TRUE(jetrace::make_builtin_track("ring", track));
        auto* r = new Race{jetrace::Scene::make(std::move(track), jetrace::PhysicsSettings{}), {}};
        jetrace::WorldState st = jetrace::start_race(r->scene, 8, 2);
        st.start_tick = 60;  // half a second on the grid first
        const auto skills = jetrace::skills_for(8, 5);
        jetrace::StepScratch scratch;
        std::vector<jetrace::Input> inputs(8);
        int after_finish = 0;
        for (std::uint32_t t = 0; t < 6000 && after_finish < 120; ++t) {
            r->history.push_back({st, inputs, 120});
            if (t == 500) jetrace::remove_car(st, 7);
            if (t == 700) jetrace::spawn_car(r->scene, st, 7, 7);
            bool all_done = true;
            for (int i = 0; i < 8; ++i) {
                inputs[i] = jetrace::drive(r->scene, st, i, skills[static_cast<std::size_t>(i)]);
                if (st.cars[static_cast<std::size_t>(i)].active && !st.cars[static_cast<std::size_t>(i)].finished)
                    all_done = false;
            }
            if (all_done) ++after_finish;
            jetrace::step(r->scene, st, inputs, scratch);
        }
        return r;
    }();
    return *race;
}

bool same_snapshot(const jp::WorldSnapshot& a, const jp::WorldSnapshot& b) {
    return jetrace::state_hash(a.state) == jetrace::state_hash(b.state) && a.last_inputs == b.last_inputs &&
           a.tick_rate_hz == b.tick_rate_hz;
}

/// decode(encode(now, base), base) == now; returns the payload size.
std::size_t round_trip(const jp::WorldSnapshot& now, const jp::WorldSnapshot* base) {
    const std::vector<std::uint8_t> bytes = jp::encode_world(now, base);
    jp::WorldSnapshot out;
    std::string error;
    EXPECT_TRUE(jp::decode_world(bytes, base, out, error)) << error;
    EXPECT_TRUE(same_snapshot(now, out)) << "tick " << now.state.tick << " baseline "
                                         << (base ? std::to_string(base->state.tick) : "none");
    return bytes.size();
}

bool moving_race(const jp::WorldSnapshot& s) {
    if (s.state.tick < s.state.start_tick + 60) return false;
    for (const jetrace::CarState& c : s.state.cars)
        if (!c.active || c.finished) return false;
    return true;
}

}  // namespace

TEST(ProtoWorld, RaceStatesRoundTripAgainstEveryBaselineAge) {
    const Race& race = ring_race();
    const auto& h = race.history;
    int finished = 0;
    for (const auto& c : h.back().state.cars) finished += c.finished ? 1 : 0;
    std::cout << "[ info ] " << h.size() << " ticks recorded, " << finished << " cars finished\n";
    EXPECT_GT(finished, 0);
    constexpr int kMaxAge = 12;
    std::vector<double> total(kMaxAge + 1, 0.0);  // [0]: no baseline
    std::vector<int> count(kMaxAge + 1, 0);
    for (std::size_t t = 0; t < h.size(); ++t) {
        const bool moving = moving_race(h[t]);
        const std::size_t none = round_trip(h[t], nullptr);
        if (moving) total[0] += static_cast<double>(none), ++count[0];
        for (int age = 1; age <= kMaxAge && static_cast<std::size_t>(age) <= t; ++age) {
            const std::size_t n = round_trip(h[t], &h[t - static_cast<std::size_t>(age)]);
            if (moving) total[static_cast<std::size_t>(age)] += static_cast<double>(n), ++count[static_cast<std::size_t>(age)];
        }
        if (::testing::Test::HasFailure()) FAIL() << "stopping at tick " << t;
    }
    std::cout << "[ info ] mean world payload bytes, 8 moving cars (" << count[0] << " ticks):\n";
    for (int age = 0; age <= kMaxAge; ++age) {
        const auto i = static_cast<std::size_t>(age);
        const double mean = total[i] / count[i];
        std::cout << "[ info ]   baseline " << (age == 0 ? std::string("none") : std::to_string(age) + " ticks old")
                  << ": " << mean << "\n";
        if (age == 0 || age == 2 || age == 4 || age == 8)
            RecordProperty("mean_bytes_" + (age == 0 ? std::string("no_baseline") : "age" + std::to_string(age)),
                           std::to_string(mean));
    }
    EXPECT_LT(total[4] / count[4], 100.0);
}

TEST(ProtoWorld, WrongBaselineNeverCrashes) {
    const auto& h = ring_race().history;
    int errors = 0, different = 0;
    for (std::size_t t = 20; t < h.size(); t += 7) {
        const auto bytes = jp::encode_world(h[t], &h[t - 4]);
        for (std::size_t wrong : {t - 1, t - 7, t - 19}) {
            jp::WorldSnapshot out;
            std::string error;
            if (!jp::decode_world(bytes, &h[wrong], out, error))
                ++errors;
            else if (!same_snapshot(out, h[t]))
                ++different;
            else
                ADD_FAILURE() << "tick " << t << ": a wrong baseline reproduced the state";
        }
        jp::WorldSnapshot out;
        std::string error;
        if (jp::decode_world(bytes, nullptr, out, error)) {
            EXPECT_FALSE(same_snapshot(out, h[t]));
        }
    }
    std::cout << "[ info ] wrong baseline: " << errors << " errors, " << different << " different states\n";
}

TEST(ProtoWorld, RejectsTruncatedTrailingAndMismatchedPayloads) {
    const auto& h = ring_race().history;
    for (std::size_t t = 13; t < h.size(); t += 97) {
        for (const jp::WorldSnapshot* base : {&h[t - 3], static_cast<const jp::WorldSnapshot*>(nullptr)}) {
            auto bytes = jp::encode_world(h[t], base);
            jp::WorldSnapshot out;
            std::string error;
            for (std::size_t len = 0; len < bytes.size(); ++len)
                EXPECT_FALSE(jp::decode_world(std::span(bytes).first(len), base, out, error)) << len;
            bytes.push_back(0);
            EXPECT_FALSE(jp::decode_world(bytes, base, out, error));
            EXPECT_NE(error.find("trailing"), std::string::npos) << error;
        }
        jp::WorldSnapshot seven = h[t - 3];
        seven.state.cars.pop_back();
        seven.last_inputs.pop_back();
        jp::WorldSnapshot out;
        std::string error;
        EXPECT_FALSE(jp::decode_world(jp::encode_world(h[t], &h[t - 3]), &seven, out, error));
        EXPECT_NE(error.find("slot count"), std::string::npos) << error;
    }
}

TEST(ProtoWorld, RandomAndMutatedPayloadsNeverCrash) {
    const auto& h = ring_race().history;
    std::mt19937_64 rng(test_seed());
    int accepted = 0;
    for (int i = 0; i < 10000; ++i) {
        const std::size_t t = 12 + rng() % (h.size() - 12);
        const jp::WorldSnapshot* base = (rng() & 1) ? &h[t - 1 - rng() % 12] : nullptr;
        std::vector<std::uint8_t> bytes;
        if (i % 4 == 0) {
            bytes.resize(rng() % 200);
            for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
        } else {
            bytes = jp::encode_world(h[t], base);
            const int flips = 1 + static_cast<int>(rng() % 3);
            for (int f = 0; f < flips; ++f) bytes[rng() % bytes.size()] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
        }
        jp::WorldSnapshot out;
        std::string error;
        if (jp::decode_world(bytes, base, out, error)) {
            ++accepted;
            // Whatever decodes is in range: it encodes and decodes again.
            jp::WorldSnapshot again;
            EXPECT_TRUE(jp::decode_world(jp::encode_world(out, base), base, again, error)) << error;
            EXPECT_TRUE(same_snapshot(out, again)) << "iteration " << i;
        } else {
            EXPECT_FALSE(error.empty());
        }
    }
    std::cout << "[ info ] random/mutated payloads accepted: " << accepted << " of 10000\n";
}

TEST(ProtoWorld, ExtremeFieldValuesRoundTrip) {
    jp::WorldSnapshot a{jetrace::make_world(4, 65535, 0xFFFFFFF0u), std::vector<jetrace::Input>(4), 10000};
    a.state.tick = 0xFFFFFFF0u;
    jetrace::CarState& c = a.state.cars[0];
    c.active = true;
    c.finished = true;
    c.position = {-0x1p21, 0x1p21 - 0x1p-10, 0x1p-10};
    c.velocity = {0x1p21 - 0x1p-10, -0x1p21, 0};
    c.orientation = jetrace::Quat(0, 0, -1, 0);
    c.next_checkpoint = 65535;
    c.respawn_checkpoint = 65535;
    c.lap = std::numeric_limits<std::int32_t>::max();
    c.finish_tick = 0xFFFFFFFFu;
    c.finish_fraction = std::nextafter(1.0, 0.0);
    c.respawns = 0xFFFFFFFFu;
    c.best_gate_distance_m = std::numeric_limits<std::int32_t>::min();
    c.no_progress_ticks = 0xFFFFFFFFu;
    a.state.cars[2] = c;
    a.state.cars[2].orientation = jetrace::Quat(0.5, -0.5, 0.5, -0.5);
    a.state.cars[2].finish_fraction = std::numeric_limits<double>::quiet_NaN();
    a.last_inputs[0] = jetrace::Input::clamped(15, -15, 1);
    jp::WorldSnapshot b = a;
    b.state.tick = 0xFFFFFFFFu;
    b.state.start_tick = 3;
    b.state.laps = 0;
    b.state.cars[0].position = {0x1p21 - 0x1p-10, -0x1p21, -0x1p-10};
    b.state.cars[0].velocity = {-0x1p21, 0x1p21 - 0x1p-10, 5.5};
    b.state.cars[0].orientation = jetrace::Quat(1, 0, 0, 0);
    b.state.cars[0].finished = false;
    b.state.cars[0].best_gate_distance_m = std::numeric_limits<std::int32_t>::max();
    b.state.cars[0].no_progress_ticks = 0;
    b.state.cars[1] = c;  // joins
    b.state.cars[2] = jetrace::CarState{};  // leaves
    b.last_inputs[3] = jetrace::Input::clamped(0, 15, 0);
    round_trip(a, nullptr);
    round_trip(b, nullptr);
    round_trip(b, &a);
    round_trip(a, &a);
    round_trip(b, &b);
    // Identical slots: 12 header bits, one bit per slot, and a 3-bit
    // upcoming-input count (zero here) per active car.
    std::size_t active = 0;
    for (const auto& car : b.state.cars) active += car.active ? 1 : 0;
    EXPECT_EQ(jp::encode_world(b, &b).size(), (12 + b.state.cars.size() + 3 * active + 7) / 8);
}

TEST(ProtoWorld, UpcomingInputsRoundTrip) {
    const Race& race = ring_race();
    jp::WorldSnapshot now = race.history[race.history.size() / 2];
    const jp::WorldSnapshot& base = race.history[race.history.size() / 2 - 2];
    now.upcoming.assign(now.state.cars.size(), {});
    for (std::size_t i = 0; i < now.state.cars.size(); ++i) {
        if (!now.state.cars[i].active) continue;
        for (std::size_t k = 0; k < i % (jp::kMaxUpcomingInputs + 1); ++k) {
            now.upcoming[i].push_back(jetrace::Input::clamped(static_cast<int>(k * 3 % 16), static_cast<int>(k) - 3, static_cast<int>(k % 2)));
        }
    }
    for (const jp::WorldSnapshot* b : {static_cast<const jp::WorldSnapshot*>(nullptr), &base}) {
        jp::WorldSnapshot out;
        std::string error;
        ASSERT_TRUE(jp::decode_world(jp::encode_world(now, b), b, out, error)) << error;
        ASSERT_EQ(out.upcoming.size(), now.state.cars.size());
        for (std::size_t i = 0; i < now.state.cars.size(); ++i) {
            ASSERT_EQ(out.upcoming[i].size(), now.upcoming[i].size()) << "slot " << i;
            for (std::size_t k = 0; k < now.upcoming[i].size(); ++k) EXPECT_EQ(out.upcoming[i][k], now.upcoming[i][k]);
        }
    }
}
