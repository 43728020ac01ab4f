// Where the client draws the cars: the others between the two stored
// snapshots around the render tick, never beyond the newest, and never along
// the line from where a car was to where it respawned; its own one where it
// is predicted, a correction fading out, unless the correction is a respawn;
// and the check of where it was drawn against the server's position.
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/client/drawn_check.hpp"
#include "jetrace/client/interpolator.hpp"
#include "jetrace/client/snapshot_store.hpp"
#include "jetrace/proto/world_codec.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace {

using jetrace::Vec3;
using jetrace::client::Interpolator;
using jetrace::client::SnapshotStore;

constexpr int kTickHz = 120;
constexpr int kSnapshotHz = 60;  // a snapshot every 2 ticks
constexpr double kPeriodUs = 1e6 / kTickHz;

class InterpolatorTest : public ::testing::Test {
protected:
    void SetUp() override {
        jetrace::Track t;
        ASSERT_TRUE(jetrace::make_builtin_track("ring", t));
        scene_ = std::make_unique<jetrace::Scene>(jetrace::Scene::make(std::move(t), jetrace::PhysicsSettings{}));
        interp_.set_rates(kTickHz, kSnapshotHz);
    }

    /// Stores a snapshot of tick `tick` with car 1 at `p` (whole metres, so
    /// quantised) having respawned `respawns` times, arriving at `now_us`.
    void add(std::uint32_t tick, const Vec3& p, std::uint32_t respawns, std::uint64_t now_us) {
        jetrace::proto::WorldSnapshot snap;
        snap.state = jetrace::start_race(*scene_, 2, 1);
        snap.state.tick = tick;
        snap.state.cars[1].position = p;
        snap.state.cars[1].respawns = respawns;
        snap.last_inputs.resize(snap.state.cars.size());
        jetrace::proto::Snapshot s;
        s.server_tick = tick;
        s.world = jetrace::proto::encode_world(snap, nullptr);
        std::string error;
        ASSERT_EQ(store_.add(s, 2, now_us, error), SnapshotStore::Added::newest) << error;
    }

    /// Where car 1 is drawn at render tick `render`, given that the newest
    /// snapshot (tick `newest`) arrived at time 0: by other() and by world().
    void drawn_at(double render, std::uint32_t newest, Vec3& other, Vec3& world) const {
        // render = newest + since - 2 snapshots (4 ticks)
        const double since = render - newest + 4.0;
        const auto now = static_cast<std::uint64_t>(std::ceil(since * kPeriodUs));  // at or just after
        EXPECT_NEAR(interp_.render_tick(store_, now, kPeriodUs), render, 1e-3);
        other = interp_.other(store_, 1, now, kPeriodUs);
        jetrace::WorldState w;
        interp_.world(store_, now, kPeriodUs, w);
        world = w.cars[1].position;
    }

    std::unique_ptr<jetrace::Scene> scene_;
    SnapshotStore store_;
    Interpolator interp_{2.0, 0.1};
};

TEST_F(InterpolatorTest, DrawsACarOnTheLineBetweenTheSnapshotsAroundTheRenderTick) {
    add(100, Vec3(0, 3, 0), 0, 0);
    add(102, Vec3(2, 3, 0), 0, 0);
    add(104, Vec3(4, 3, 0), 0, 0);
    Vec3 other, world;
    drawn_at(101.0, 104, other, world);
    EXPECT_NEAR(other.x(), 1.0, 1e-3);
    EXPECT_EQ(other, world);
    drawn_at(103.5, 104, other, world);
    EXPECT_NEAR(other.x(), 3.5, 1e-3);
    EXPECT_EQ(other, world);
    // Past the newest snapshot: held there, not extrapolated.
    drawn_at(106.0, 104, other, world);
    EXPECT_EQ(other, Vec3(4, 3, 0));
    EXPECT_EQ(world, Vec3(4, 3, 0));
}

TEST_F(InterpolatorTest, ACarThatRespawnedJumpsWithoutSlidingAcrossTheTrack) {
    add(100, Vec3(0, 3, 0), 0, 0);
    add(102, Vec3(2, 3, 0), 0, 0);
    add(104, Vec3(-40, 3, 60), 1, 0);  // respawned at its last gate
    Vec3 other, world;
    for (double render = 102.0; render < 104.0; render += 0.25) {
        drawn_at(render, 104, other, world);
        EXPECT_EQ(other, Vec3(2, 3, 0)) << "render tick " << render;
        EXPECT_EQ(world, Vec3(2, 3, 0)) << "render tick " << render;
    }
    drawn_at(104.0, 104, other, world);
    EXPECT_EQ(other, Vec3(-40, 3, 60));
    EXPECT_EQ(world, Vec3(-40, 3, 60));
    // Before the respawn it is interpolated as usual.
    drawn_at(101.0, 104, other, world);
    EXPECT_NEAR(other.x(), 1.0, 1e-3);
}

TEST(Interpolator, AnOwnCarsCorrectionFadesButARespawnIsDrawnAtOnce) {
    Interpolator interp(2.0, 0.25);
    // Predicted at (0, 3, 0), corrected to (1, 3, 0): still drawn where it was.
    interp.correct(Vec3(0, 3, 0), Vec3(1, 3, 0), false);
    EXPECT_EQ(interp.own(Vec3(1, 3, 0)), Vec3(0, 3, 0));
    interp.tick();  // a quarter of the offset gone
    EXPECT_NEAR(interp.own(Vec3(1, 3, 0)).x(), 0.25, 1e-12);
    // A correction that respawned it (or took a respawn back): drawn at once.
    interp.correct(Vec3(1, 3, 0), Vec3(-40, 3, 60), true);
    EXPECT_EQ(interp.own(Vec3(-40, 3, 60)), Vec3(-40, 3, 60));
    interp.tick();
    EXPECT_EQ(interp.own(Vec3(-40, 3, 60)), Vec3(-40, 3, 60));
}

TEST(Interpolator, AFadedOffsetIsGoneAndTheCarIsDrawnExactlyWherePredicted) {
    Interpolator interp(2.0, 0.25);
    interp.correct(Vec3(0, 3, 0), Vec3(0.01, 3, 0), false);  // 1 cm
    int ticks = 0;
    while (interp.smoothing() && ticks < 1000) {
        interp.tick();
        ++ticks;
    }
    // 0.01 * 0.75^n under 1e-6 m: n = 33.
    EXPECT_EQ(ticks, 33);
    const Vec3 p(0.1 + 0.2, -0.0, 1e300);  // bits addition could change (-0 + 0 = +0)
    EXPECT_EQ(std::signbit(interp.own(p).y()), true);
    EXPECT_EQ(interp.own(p), p);
}

TEST(DrawnCheck, ComparesEachDrawnTickOnceBitForBitAndNamesTheCause) {
    using jetrace::client::DrawnCause;
    jetrace::client::DrawnCheck check;
    EXPECT_FALSE(check.confirm(10, Vec3(1, 2, 3), DrawnCause::none)) << "nothing drawn at tick 10";
    check.record(10, Vec3(1, 2, 3), false, DrawnCause::none);
    check.record(10, Vec3(9, 9, 9), false, DrawnCause::none);  // drawn again: the first drawing counts
    ASSERT_TRUE(check.confirm(10, Vec3(1, 2, 3), DrawnCause::near_car));
    EXPECT_TRUE(check.last().same);
    EXPECT_EQ(check.last().cause, DrawnCause::none) << "no cause for a tick drawn right";
    EXPECT_FALSE(check.confirm(10, Vec3(1, 2, 3), DrawnCause::none)) << "compared once";
    // One ulp off is off.
    check.record(11, Vec3(1, 2, 3), false, DrawnCause::none);
    ASSERT_TRUE(check.confirm(11, Vec3(1, 2, std::nextafter(3.0, 4.0)), DrawnCause::none));
    EXPECT_FALSE(check.last().same);
    EXPECT_EQ(check.last().cause, DrawnCause::none) << "unexplained";
    // The snapshot's cause first; else the cause of the fading offset.
    check.record(12, Vec3(1, 2, 3), true, DrawnCause::near_car);
    ASSERT_TRUE(check.confirm(12, Vec3(1, 2, 4), DrawnCause::late_input));
    EXPECT_EQ(check.last().cause, DrawnCause::late_input);
    check.record(13, Vec3(1, 2, 3), true, DrawnCause::near_car);
    ASSERT_TRUE(check.confirm(13, Vec3(1, 2, 4), DrawnCause::none));
    EXPECT_EQ(check.last().cause, DrawnCause::near_car);
    EXPECT_TRUE(check.last().smoothing);
    EXPECT_EQ(check.last().tick, 13u);
    // A tick the ring has dropped (256 later) is not compared.
    check.record(14, Vec3(1, 2, 3), false, DrawnCause::none);
    check.record(14 + 256, Vec3(1, 2, 3), false, DrawnCause::none);
    EXPECT_FALSE(check.confirm(14, Vec3(1, 2, 3), DrawnCause::none));
}

}  // namespace
