// Welcome.physics (protocol version 3): every PhysicsSettings field crosses
// the wire exactly, and settings the core does not have are rejected.
#include "jetrace/proto/messages.hpp"
#include "jetrace_generated.h"
#include "support/wire_craft.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace jp = jetrace::proto;
namespace fb = flatbuffers;
namespace w = jetrace::wire;
using jetrace::test::finish;

namespace {

jp::Welcome welcome_with(const jetrace::PhysicsSettings& s) {
    jp::Welcome m;
    m.slot = 0;
    m.max_players = 4;
    m.tick_rate_hz = static_cast<std::uint16_t>(s.tick_rate_hz);
    m.track_name = "ring";
    m.physics_hash = jp::physics_hash(s);
    m.physics = s;
    return m;
}

std::vector<std::uint8_t> crafted(std::uint8_t integrator, double gravity, std::uint16_t physics_tick_rate = 120) {
    fb::FlatBufferBuilder b;
    auto name = b.CreateString("ring");
    auto physics = w::CreatePhysicsSettings(b, physics_tick_rate, gravity, 2.5, 24, 1.8e-4, 30, 1.6, 40, 15, 12, 0.5, 10, 20, 1,
                                            1.0 / 1024, 0.05, 1, 4, integrator, true);
    return finish(b, w::CreateWelcome(b, 3, 0, 4, 120, 60, name, 0, 0, 0, 0, physics), "JWLC");
}

}  // namespace

TEST(WelcomePhysics, EveryFieldRoundTrips) {
    jetrace::PhysicsSettings s;
    s.tick_rate_hz = 240;
    s.gravity_mps2 = 9.5;
    s.no_progress_s = 7.25;
    s.resolver_passes = 17;
    s.push_out = jetrace::PushOut::first_contact;
    s.collision_mode = jetrace::CollisionMode::discrete;
    s.sweep_contacts = 3;
    s.integrator = jetrace::Integrator::semi_implicit_euler;
    s.quantize_state = false;
    jp::Message m;
    std::string error;
    ASSERT_TRUE(jp::decode(jp::encode(welcome_with(s)), m, error)) << error;
    const auto& got = std::get<jp::Welcome>(m);
    ASSERT_TRUE(got.physics.has_value());
    // The hash covers every field's raw bits: equal hashes, equal settings.
    EXPECT_EQ(jp::physics_hash(*got.physics), jp::physics_hash(s));
    EXPECT_EQ(got.physics->tick_rate_hz, 240);
    EXPECT_EQ(got.physics->integrator, jetrace::Integrator::semi_implicit_euler);
    EXPECT_FALSE(got.physics->quantize_state);
}

TEST(WelcomePhysics, DefaultSettingsRoundTrip) {
    const jetrace::PhysicsSettings s;
    jp::Message m;
    std::string error;
    ASSERT_TRUE(jp::decode(jp::encode(welcome_with(s)), m, error)) << error;
    EXPECT_EQ(jp::physics_hash(*std::get<jp::Welcome>(m).physics), jp::physics_hash(s));
}

TEST(WelcomePhysics, RejectsWhatTheCoreDoesNotHave) {
    jp::Message m;
    std::string error;
    ASSERT_TRUE(jp::decode(crafted(2, 9.81), m, error)) << error;
    EXPECT_FALSE(jp::decode(crafted(3, 9.81), m, error));
    EXPECT_NE(error.find("Welcome.physics: unknown integrator"), std::string::npos) << error;
    EXPECT_FALSE(jp::decode(crafted(2, std::numeric_limits<double>::quiet_NaN()), m, error));
    EXPECT_NE(error.find("Welcome.physics: a setting is not a finite number"), std::string::npos) << error;
}

// Settings of the right types that the core cannot step (found by the
// message_decode fuzzer: a zero tick rate decoded, then tripped encode's
// assert) are refused by the core's own validate(), and a physics table
// whose tick rate differs from the Welcome's is refused.
TEST(WelcomePhysics, RejectsSettingsTheCoreCannotStep) {
    jp::Message m;
    std::string error;
    EXPECT_FALSE(jp::decode(crafted(2, 9.81, 0), m, error));
    EXPECT_NE(error.find("Welcome.physics: tick_rate_hz must be in [10, 10000]"), std::string::npos) << error;
    EXPECT_FALSE(jp::decode(crafted(2, -9.81), m, error));
    EXPECT_NE(error.find("Welcome.physics: gravity_mps2 must be >= 0"), std::string::npos) << error;
    EXPECT_FALSE(jp::decode(crafted(2, 9.81, 240), m, error));
    EXPECT_NE(error.find("Welcome.physics.tick_rate_hz: differs from Welcome.tick_rate_hz"), std::string::npos)
        << error;
}

TEST(WelcomePhysics, ProtocolVersionIsSix) { EXPECT_EQ(jp::kProtocolVersion, 6); }
