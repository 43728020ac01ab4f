// The world payload inside snapshots (jetrace::proto::encode_world and
// decode_world): real race states round-trip bit for bit against any
// baseline; wrong baselines, truncated, mutated and random payloads are
// rejected without crashing.
#include "jetrace/ai/driver_ai.hpp"
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/proto/world_codec.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "support/test_seed.hpp"
#include "support/wire_craft.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace jp = jetrace::proto;

namespace {
std::uint64_t test_seed() { return jetrace::test::test_seed(20240521u); }
using jetrace::test::Bits;
}  // namespace

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
        const jetrace::Course course(r->scene);
        jetrace::StepScratch scratch;
        std::vector<jetrace::Input> inputs(8);
        int after_finish = 0;
        for (std::uint32_t t = 0; t < 6000 && after_finish < 120; ++t) {
            r->history.push_back({st, inputs, 120, {}});
            if (t == 500) jetrace::remove_car(st, 7);
            if (t == 700) jetrace::spawn_car(r->scene, st, 7, 7);
            bool all_done = true;
            for (int i = 0; i < 8; ++i) {
                inputs[i] = jetrace::drive(course, st, i, skills[static_cast<std::size_t>(i)]);
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
    jp::WorldSnapshot a{jetrace::make_world(4, 65535, 0xFFFFFFF0u), std::vector<jetrace::Input>(4), 10000, {}};
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
    // Identical slots: 12 header bits, one bit per slot, and a 4-bit
    // upcoming-input count (zero here) per active car.
    std::size_t active = 0;
    for (const auto& car : b.state.cars) active += car.active ? 1 : 0;
    EXPECT_EQ(jp::encode_world(b, &b).size(), (12 + b.state.cars.size() + 4 * active + 7) / 8);
}

TEST(ProtoWorld, RejectsInputsThatPackNeverProduces) {
    // No baseline: tick, tick rate, start tick, laps, one inactive slot whose
    // last input has steer bits 31 (steer +16).
    const auto payload = Bits{}.u(7, 32).u(120, 16).u(0, 32).u(1, 16).u(1, 7).u(0, 1).u(0, 1);
    jp::WorldSnapshot out;
    std::string error;
    EXPECT_TRUE(jp::decode_world(Bits{payload}.u(0x1E0, 10).bytes(), nullptr, out, error)) << error;
    EXPECT_FALSE(jp::decode_world(Bits{payload}.u(0x1F0, 10).bytes(), nullptr, out, error));
    EXPECT_NE(error.find("last input"), std::string::npos) << error;
}

TEST(ProtoWorld, UpcomingInputsRoundTrip) {
    const Race& race = ring_race();
    jp::WorldSnapshot now = race.history[race.history.size() / 2];
    const jp::WorldSnapshot& base = race.history[race.history.size() / 2 - 2];
    now.upcoming.assign(now.state.cars.size(), {});
    // Counts over the whole range of the 4-bit field, and one over it
    // (slot 1: the encoder keeps the first kMaxUpcomingInputs).
    for (std::size_t i = 0; i < now.state.cars.size(); ++i) {
        if (!now.state.cars[i].active) continue;
        const std::size_t count = i == 1 ? jp::kMaxUpcomingInputs + 1 : (i * 5) % (jp::kMaxUpcomingInputs + 1);
        for (std::size_t k = 0; k < count; ++k) {
            now.upcoming[i].push_back(jetrace::Input::clamped(static_cast<int>(k * 3 % 16), static_cast<int>(k) - 3, static_cast<int>(k % 2)));
        }
    }
    for (const jp::WorldSnapshot* b : {static_cast<const jp::WorldSnapshot*>(nullptr), &base}) {
        jp::WorldSnapshot out;
        std::string error;
        ASSERT_TRUE(jp::decode_world(jp::encode_world(now, b), b, out, error)) << error;
        ASSERT_EQ(out.upcoming.size(), now.state.cars.size());
        std::size_t largest = 0;
        for (std::size_t i = 0; i < now.state.cars.size(); ++i) {
            const std::size_t kept = std::min(now.upcoming[i].size(), jp::kMaxUpcomingInputs);
            ASSERT_EQ(out.upcoming[i].size(), kept) << "slot " << i;
            for (std::size_t k = 0; k < kept; ++k) EXPECT_EQ(out.upcoming[i][k], now.upcoming[i][k]);
            largest = std::max(largest, out.upcoming[i].size());
        }
        EXPECT_EQ(largest, jp::kMaxUpcomingInputs) << "no slot carried the most upcoming inputs";
    }
}
