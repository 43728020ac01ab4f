// Where RaceClient draws its own car, over a scripted transport (no network):
// a snapshot that corrects the prediction leaves the car drawn where it was,
// the offset fading, but a snapshot in which the server respawned the car
// (its prediction had not) draws it at once where it now is predicted.
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/client/race_client.hpp"
#include "jetrace/proto/world_codec.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "support/scripted_transport.hpp"
#include "support/welcome.hpp"

#include <gtest/gtest.h>

namespace {

using namespace jetrace;

Input no_input(const Scene&, const WorldState&, int) { return Input{}; }

class OwnCarDrawing : public ::testing::Test {
protected:
    OwnCarDrawing() : client_(client::ClientConfig{}, client::KnownScenes{&scene_}, transport_) {}

    void SetUp() override {
        transport_.connect();
        update_for(0.01);
        deliver(test::welcome_for(scene_, 0));
        proto::RaceStatus racing;
        racing.phase = proto::RacePhase::racing;
        racing.race_number = 1;
        deliver(racing);
        // The server's world: two cars on ring, racing for 2 s.
        server_ = start_race(scene_, 2, 1);
        StepScratch scratch;
        const std::vector<Input> inputs(2);
        while (server_.tick < 240) step(scene_, server_, inputs, scratch);
        send_snapshot(server_);
        update_for(0.2);
        ASSERT_EQ(client_.state(), client::ClientState::racing) << client_.close_reason();
        ASSERT_GT(client_.predicted_tick(), server_.tick);
    }

    void deliver(const proto::Message& m) { transport_.deliver(0, net::Channel::reliable, proto::encode(m)); }
    void send_snapshot(const WorldState& w) {
        proto::WorldSnapshot snap;
        snap.state = w;
        snap.last_inputs.resize(w.cars.size());
        proto::Snapshot s;
        s.server_tick = w.tick;
        s.phase = proto::RacePhase::racing;
        s.race_number = 1;
        s.world = proto::encode_world(snap, nullptr);
        transport_.deliver(0, net::Channel::unreliable, proto::encode(s));
    }
    void update_for(double seconds) {
        for (const std::uint64_t end = now_us_ + static_cast<std::uint64_t>(seconds * 1e6); now_us_ < end;) {
            now_us_ += 1000;
            client_.update(now_us_, no_input);
        }
    }
    /// How far from its predicted place the own car is drawn (unit: m).
    double drawn_off() const {
        return (client_.visual_own_position() - client_.predicted().cars[0].position).norm();
    }
    /// The server's world 2 ticks on, with the own car moved by `shift`.
    WorldState next_server_world(const Vec3& shift, std::uint32_t respawns) {
        StepScratch scratch;
        const std::vector<Input> inputs(2);
        step(scene_, server_, inputs, scratch);
        step(scene_, server_, inputs, scratch);
        WorldState w = server_;
        w.cars[0].position += shift;
        w.cars[0].respawns += respawns;
        return w;
    }

    Scene scene_ = Scene::make(make_oval(ring_params()), PhysicsSettings{});
    test::ScriptedTransport transport_;
    client::RaceClient client_;
    WorldState server_;
    std::uint64_t now_us_ = 0;
};

TEST_F(OwnCarDrawing, ACorrectionFadesFromWhereTheCarWasDrawn) {
    EXPECT_EQ(drawn_off(), 0.0);
    send_snapshot(next_server_world(Vec3(0, 0, 1), 0));  // 1 m sideways: a correction
    update_for(0.001);
    EXPECT_GT(client_.stats().corrections, 0u);
    EXPECT_NEAR(drawn_off(), 1.0, 0.2) << "drawn where it was, not where it jumped";
    update_for(0.5);
    EXPECT_LT(drawn_off(), 0.01) << "the offset faded";
}

TEST_F(OwnCarDrawing, ARespawnTheCorrectionBringsIsDrawnAtOnce) {
    // The server respawned the car at gate 4, about 100 m on (the
    // prediction had not).
    const Pose& gate = scene_.track.checkpoints[4].respawn;
    WorldState w = next_server_world(Vec3::Zero(), 1);
    place_car(w.cars[0], gate);
    send_snapshot(w);
    update_for(0.001);
    EXPECT_GT(client_.stats().max_correction_m, 30.0);
    EXPECT_EQ(drawn_off(), 0.0) << "a respawned car slides from where it was";
}

}  // namespace
