// Continuous collision (CollisionMode::swept): the swept sphere against one
// triangle in each feature region. The whole step against a zero-thickness
// wall (no pass-through to 2,000 m/s in the default mode; the discrete
// push-out's limit at r/dt) is in test_failure_modes.cpp.
#include "jetrace/core/sweep.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace jetrace;

namespace {

// The triangle (0,0,0) (10,0,0) (0,0,10) in the floor plane, normal +Y
// ((a, c, b) order gives +Y by the right-hand rule).
Triangle floor_triangle() { return Triangle::make(Vec3(0, 0, 0), Vec3(0, 0, 10), Vec3(10, 0, 0)); }

}  // namespace

TEST(Sweep, FaceHitAtExactTime) {
    const Triangle t = floor_triangle();
    ASSERT_NEAR(t.normal().y(), 1.0, 1e-15);
    SweepHit hit;
    // Centre from y = 10.5 straight down by 16: touches at y = 2.5, t = 0.5.
    ASSERT_TRUE(sweep_sphere_triangle(Vec3(2, 10.5, 2), Vec3(0, -16, 0), 2.5, t, hit));
    EXPECT_DOUBLE_EQ(hit.t, 0.5);
    EXPECT_EQ(hit.normal, Vec3(0, 1, 0));
    // From below, the face's back side: the normal points down.
    SweepHit below;
    ASSERT_TRUE(sweep_sphere_triangle(Vec3(2, -10.5, 2), Vec3(0, 16, 0), 2.5, t, below));
    EXPECT_DOUBLE_EQ(below.t, 0.5);
    EXPECT_EQ(below.normal, Vec3(0, -1, 0));
}

TEST(Sweep, EdgeAndVertexHits) {
    const Triangle t = floor_triangle();
    // Beside the edge x = 0 (z in [0, 10]), moving +x at the plane's height:
    // the cylinder around the edge is reached at x = -2.5.
    SweepHit edge;
    ASSERT_TRUE(sweep_sphere_triangle(Vec3(-12.5, 0, 5), Vec3(20, 0, 0), 2.5, t, edge));
    EXPECT_NEAR(edge.t, 0.5, 1e-12);
    EXPECT_NEAR(edge.normal.x(), -1.0, 1e-12);
    // Towards the vertex (0,0,0) along the diagonal from outside.
    SweepHit vertex;
    const Vec3 dir = Vec3(1, 0, 1).normalized();
    ASSERT_TRUE(sweep_sphere_triangle(-dir * 12.5, dir * 20.0, 2.5, t, vertex));
    EXPECT_NEAR(vertex.t, 0.5, 1e-12);
    EXPECT_NEAR((vertex.normal + dir).norm(), 0.0, 1e-12);
}

TEST(Sweep, MissesAndMovingAway) {
    const Triangle t = floor_triangle();
    SweepHit hit;
    EXPECT_FALSE(sweep_sphere_triangle(Vec3(30, 10, 30), Vec3(0, -20, 0), 2.5, t, hit));  // beside it
    EXPECT_FALSE(sweep_sphere_triangle(Vec3(2, 3, 2), Vec3(0, 20, 0), 2.5, t, hit));      // leaving
    EXPECT_FALSE(sweep_sphere_triangle(Vec3(2, 2.6, 2), Vec3(5, 0, 0), 2.5, t, hit));     // parallel, clear
    EXPECT_FALSE(sweep_sphere_triangle(Vec3(2, 20, 2), Vec3(0, -5, 0), 2.5, t, hit));     // stops short
    EXPECT_EQ(hit.t, 1.0);
}

TEST(Sweep, TouchingFaceAndMovingInHitsAtOnce) {
    SweepHit hit;
    ASSERT_TRUE(sweep_sphere_triangle(Vec3(2, 2.0, 2), Vec3(0, -30, 0), 2.5, floor_triangle(), hit));
    EXPECT_EQ(hit.t, 0.0);
    EXPECT_EQ(hit.normal, Vec3(0, 1, 0));
}

TEST(Sweep, KeepsTheEarliestOverSeveralTriangles) {
    const Triangle near_t = Triangle::make(Vec3(0, 5, 0), Vec3(0, 5, 10), Vec3(10, 5, 0));
    SweepHit hit;
    EXPECT_TRUE(sweep_sphere_triangle(Vec3(2, 20, 2), Vec3(0, -20, 0), 2.5, floor_triangle(), hit));
    EXPECT_TRUE(sweep_sphere_triangle(Vec3(2, 20, 2), Vec3(0, -20, 0), 2.5, near_t, hit));
    EXPECT_FALSE(sweep_sphere_triangle(Vec3(2, 20, 2), Vec3(0, -20, 0), 2.5, floor_triangle(), hit));
    EXPECT_DOUBLE_EQ(hit.t, (20.0 - 5.0 - 2.5) / 20.0);
}
