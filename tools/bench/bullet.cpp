// Side by side with Bullet (issue 4). Scenarios, each run by both systems:
//   idle      one car at rest on the stadium's pole position;
//   driving   one car at 100 m/s at full thrust down the stadium's second
//             straight (jetrace: throttle; Bullet: a central force of the
//             same acceleration, frictionless sphere);
//   thin_wall a car sliding into a zero-thickness wall (lab::thin_wall_mesh)
//             over the same grid of approach phases and offsets: the cost of
//             a step at 200 m/s and the tunnelling limit of jetrace's modes
//             and of Bullet with and without its swept-sphere CCD.
// Bullet is the Debian build (single precision). Only stepping is timed, in
// thread CPU time (the thin wall's runs are 8 steps each: the clock's own
// cost is subtracted on both sides).
#include "bench/bullet.hpp"

#include "bench/common.hpp"
#include "lab/probes.hpp"

#include <BulletCollision/CollisionDispatch/btInternalEdgeUtility.h>
#include <btBulletDynamicsCommon.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

namespace jetrace::bench {
namespace {

btVector3 bt(const Vec3& v) {
    return {static_cast<btScalar>(v.x()), static_cast<btScalar>(v.y()), static_cast<btScalar>(v.z())};
}

// Bullet's fix for bumps at internal mesh edges, enabled per scene below.
bool adjust_internal_edges(btManifoldPoint& cp, const btCollisionObjectWrapper* a, int part_a, int index_a,
                           const btCollisionObjectWrapper* b, int part_b, int index_b) {
    btAdjustInternalEdgeContacts(cp, b, a, part_b, index_b);
    (void)part_a, (void)index_a;
    return true;
}

// A Bullet world holding a static triangle mesh and one sphere. With
// `internal_edges`, btGenerateInternalEdgeInfo and btAdjustInternalEdgeContacts
// (Bullet's remedy for ghost collisions at triangle seams) are on.
class BulletScene {
public:
    BulletScene(const Track& track, double radius_m, double gravity_mps2, bool internal_edges = false)
        : sphere_(static_cast<btScalar>(radius_m)) {
        for (const Triangle& t : track.triangles) mesh_.addTriangle(bt(t.a), bt(t.b), bt(t.c), false);
        shape_ = std::make_unique<btBvhTriangleMeshShape>(&mesh_, true);
        world_.setGravity(btVector3(0, static_cast<btScalar>(-gravity_mps2), 0));
        btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, shape_.get());
        ground_ = std::make_unique<btRigidBody>(info);
        ground_->setFriction(0);
        if (internal_edges) {
            btGenerateInternalEdgeInfo(shape_.get(), &edges_);
            ground_->setCollisionFlags(ground_->getCollisionFlags() |
                                       btCollisionObject::CF_CUSTOM_MATERIAL_CALLBACK);
            gContactAddedCallback = adjust_internal_edges;
        }
        world_.addRigidBody(ground_.get());
    }
    ~BulletScene() {
        remove_car();
        world_.removeRigidBody(ground_.get());
    }

    /// Puts the sphere at `p` with velocity `v`. The body is created once and
    /// then moved, its cached contacts dropped (as a teleport in a game would).
    void place(const Vec3& p, const Vec3& v, bool ccd, double radius_m) {
        btTransform tr;
        tr.setIdentity();
        tr.setOrigin(bt(p));
        if (!car_) {
            btVector3 inertia(0, 0, 0);
            sphere_.calculateLocalInertia(1, inertia);
            motion_ = std::make_unique<btDefaultMotionState>(tr);
            btRigidBody::btRigidBodyConstructionInfo info(1, motion_.get(), &sphere_, inertia);
            car_ = std::make_unique<btRigidBody>(info);
            car_->setFriction(0);
            car_->setRestitution(0);
            car_->setActivationState(DISABLE_DEACTIVATION);
            world_.addRigidBody(car_.get());
        }
        car_->setWorldTransform(tr);
        car_->setInterpolationWorldTransform(tr);
        motion_->setWorldTransform(tr);
        car_->setLinearVelocity(bt(v));
        car_->setAngularVelocity(btVector3(0, 0, 0));
        car_->clearForces();
        car_->setCcdMotionThreshold(ccd ? static_cast<btScalar>(0.5 * radius_m) : 0);
        car_->setCcdSweptSphereRadius(ccd ? static_cast<btScalar>(0.9 * radius_m) : 0);
        world_.updateSingleAabb(car_.get());
        world_.getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(car_->getBroadphaseHandle(),
                                                                               &dispatcher_);
    }
    void step(double dt, const Vec3& force) {
        if (force.squaredNorm() > 0) car_->applyCentralForce(bt(force));
        world_.stepSimulation(static_cast<btScalar>(dt), 0);  // exactly one step of dt
    }
    double x() const { return car_->getWorldTransform().getOrigin().x(); }
    double y() const { return car_->getWorldTransform().getOrigin().y(); }

private:
    void remove_car() {
        if (car_) world_.removeRigidBody(car_.get());
        car_.reset();
    }
    btDefaultCollisionConfiguration config_;
    btCollisionDispatcher dispatcher_{&config_};
    btDbvtBroadphase broadphase_;
    btSequentialImpulseConstraintSolver solver_;
    btDiscreteDynamicsWorld world_{&dispatcher_, &broadphase_, &solver_, &config_};
    btTriangleMesh mesh_;
    btTriangleInfoMap edges_;
    std::unique_ptr<btBvhTriangleMeshShape> shape_;
    std::unique_ptr<btRigidBody> ground_;
    btSphereShape sphere_;
    std::unique_ptr<btDefaultMotionState> motion_;
    std::unique_ptr<btRigidBody> car_;
};

struct Straight {
    Vec3 start, velocity, forward;
    Input input;
};

// ns per step of one jetrace car from `start` for `frames` steps. Never
// inlined, so that callgrind can count only it: docs/ACCURACY.md runs
// valgrind --tool=callgrind --collect-atstart=no --toggle-collect='*jetrace_timed_run*'.
[[gnu::noinline]] double jetrace_timed_run(const Scene& sc, const Straight& s, int frames) {
    WorldState st = lab::one_car(s.start, s.forward, s.velocity);
    StepScratch scratch;
    const CpuTimer timer;
    for (int i = 0; i < frames; ++i) step(sc, st, {&s.input, 1}, scratch);
    return timer.ns() / frames;
}

double bullet_run(BulletScene& b, const PhysicsSettings& ps, const Straight& s, int frames) {
    b.place(s.start, s.velocity, false, ps.car_radius_m);
    const Vec3 force = s.forward * (ps.thrust_mps2 * s.input.throttle / Input::kMaxThrottle);
    const CpuTimer timer;
    for (int i = 0; i < frames; ++i) b.step(ps.dt_s(), force);
    return timer.ns() / frames;
}

// Height above the start of each system over `frames` steps (untimed):
// bumps at the floor's seams.
struct Excursions {
    double ours_max_m = 0, theirs_max_m = 0;
    /// Share of steps Bullet's sphere ended more than 1 cm above where it
    /// settled (off the floor: nothing to collide with).
    double theirs_airborne_fraction = 0;
};

Excursions height_excursions(const Scene& sc, BulletScene& b, const Straight& s, int frames) {
    const PhysicsSettings& ps = sc.physics;
    WorldState st = lab::one_car(s.start, s.forward, s.velocity);
    StepScratch scratch;
    const double y0 = st.cars[0].position.y();
    Excursions e;
    for (int i = 0; i < frames; ++i) {
        step(sc, st, {&s.input, 1}, scratch);
        e.ours_max_m = std::max(e.ours_max_m, std::abs(st.cars[0].position.y() - y0));
    }
    // Bullet rests its sphere on the mesh's collision margin: start from where it settles.
    b.place(s.start, s.velocity, false, ps.car_radius_m);
    const Vec3 force = s.forward * (ps.thrust_mps2 * s.input.throttle / Input::kMaxThrottle);
    b.step(ps.dt_s(), force);
    const double by0 = b.y();
    int airborne = 0;
    for (int i = 1; i < frames; ++i) {
        b.step(ps.dt_s(), force);
        e.theirs_max_m = std::max(e.theirs_max_m, std::abs(b.y() - by0));
        airborne += b.y() - by0 > 0.01 ? 1 : 0;
    }
    e.theirs_airborne_fraction = frames > 1 ? static_cast<double>(airborne) / (frames - 1) : 0.0;
    return e;
}

// Prints the scenario's JSON line with both systems' timings (jetrace's
// only when `theirs` is empty: --jetrace-only).
void print(nlohmann::json& j, const std::vector<double>& ours, const std::vector<double>& theirs) {
    j["jetrace_ns_per_step"] = median(ours);
    // Bullet's runs are bimodal on a loaded machine; the fastest runs as well.
    j["jetrace_min_ns_per_step"] = *std::min_element(ours.begin(), ours.end());
    j["jetrace_runs_ns"] = ours;
    if (!theirs.empty()) {
        j["bullet_ns_per_step"] = median(theirs);
        j["bullet_over_jetrace"] = median(theirs) / median(ours);
        j["bullet_over_jetrace_by_round"] = median_ratio(theirs, ours);
        j["bullet_min_ns_per_step"] = *std::min_element(theirs.begin(), theirs.end());
        j["bullet_runs_ns"] = theirs;
    }
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
}

void straight_scenario(const char* name, const Straight& s, const BulletOptions& o, const PhysicsSettings& ps) {
    const Scene sc = Scene::make(make_oval(stadium_params()), ps);
    nlohmann::json j;
    j["scenario"] = name;
    j["tick_rate_hz"] = ps.tick_rate_hz;
    j["frames"] = o.frames;
    j["repeats"] = o.repeats;
    j["triangles"] = sc.track.triangles.size();
    std::vector<double> ours, theirs;
    if (o.jetrace_only) {
        for (int r = 0; r < o.repeats; ++r) ours.push_back(jetrace_timed_run(sc, s, o.frames));
        print(j, ours, theirs);
        return;
    }
    // Plain Bullet and Bullet with its internal-edge fix, each round timing
    // all three systems in turn, so that the machine's drift affects each
    // alike. (The fix installs a global contact callback, which only the
    // fixed scene's ground asks for.)
    BulletScene b(sc.track, ps.car_radius_m, ps.gravity_mps2);
    BulletScene fixed(sc.track, ps.car_radius_m, ps.gravity_mps2, true);
    std::vector<double> fixed_ns;
    for (int r = 0; r < o.repeats; ++r) {
        ours.push_back(jetrace_timed_run(sc, s, o.frames));
        theirs.push_back(bullet_run(b, ps, s, o.frames));
        fixed_ns.push_back(bullet_run(fixed, ps, s, o.frames));
    }
    const Excursions ex = height_excursions(sc, b, s, o.frames);
    j["jetrace_max_height_change_m"] = ex.ours_max_m;
    j["bullet_max_height_change_m"] = ex.theirs_max_m;
    j["bullet_airborne_fraction"] = ex.theirs_airborne_fraction;
    const Excursions fixed_ex = height_excursions(sc, fixed, s, o.frames);
    j["bullet_internal_edges_max_height_change_m"] = fixed_ex.theirs_max_m;
    j["bullet_internal_edges_airborne_fraction"] = fixed_ex.theirs_airborne_fraction;
    j["bullet_internal_edges_ns_per_step"] = median(fixed_ns);
    j["bullet_internal_edges_over_jetrace"] = median(fixed_ns) / median(ours);
    j["bullet_internal_edges_over_jetrace_by_round"] = median_ratio(fixed_ns, ours);
    j["bullet_internal_edges_runs_ns"] = fixed_ns;
    print(j, ours, theirs);
}

// Bullet: does the sphere pass the wall at `speed` for any approach?
bool bullet_passes(BulletScene& b, const PhysicsSettings& ps, double speed, const lab::Approach& a, bool ccd,
                   double* ns_total = nullptr, long* steps = nullptr) {
    bool passed = false;
    for (int p = 0; p < a.phases; ++p) {
        for (int l = 0; l < a.laterals; ++l) {
            b.place(lab::approach_start(ps, speed, a, p, l), Vec3(speed, 0, 0), ccd, ps.car_radius_m);
            const CpuTimer timer;
            for (int i = 0; i < lab::kApproachSteps; ++i) {
                b.step(ps.dt_s(), Vec3::Zero());
                if (b.x() > 0.0) passed = true;
            }
            if (ns_total != nullptr) *ns_total += timer.ns() - cpu_timer_overhead_ns(), *steps += lab::kApproachSteps;
            if (passed && ns_total == nullptr) return true;
        }
    }
    return passed;
}

// jetrace: ns per step over the approach grid at `speed`.
double jetrace_wall_ns(const Scene& sc, double speed, const lab::Approach& a) {
    double ns = 0;
    StepScratch scratch;
    const Input coast{};
    for (int p = 0; p < a.phases; ++p) {
        for (int l = 0; l < a.laterals; ++l) {
            WorldState st = lab::one_car(lab::approach_start(sc.physics, speed, a, p, l), Vec3(1, 0, 0), Vec3(speed, 0, 0));
            const CpuTimer timer;
            for (int i = 0; i < lab::kApproachSteps; ++i) step(sc, st, {&coast, 1}, scratch);
            ns += timer.ns() - cpu_timer_overhead_ns();
        }
    }
    return ns / (a.phases * a.laterals * lab::kApproachSteps);
}

void thin_wall_scenario(const BulletOptions& o, const PhysicsSettings& ps) {
    const lab::Approach a = o.quick ? lab::Approach{4, 2} : lab::Approach{16, 4};
    const double ratio = o.quick ? 1.25 : 1.03, hi = 4000.0, timed_speed = 200.0;
    const Scene def = lab::make_lab_scene(lab::thin_wall_mesh(), ps);
    PhysicsSettings discrete_ps = ps;
    lab::set_swept(discrete_ps, false);
    const Scene discrete = lab::make_lab_scene(lab::thin_wall_mesh(), discrete_ps);
    BulletScene b(def.track, ps.car_radius_m, ps.gravity_mps2);

    std::vector<double> ours, ours_discrete, theirs_ccd, theirs;
    for (int r = 0; r < o.repeats; ++r) {
        ours.push_back(jetrace_wall_ns(def, timed_speed, a));
        ours_discrete.push_back(jetrace_wall_ns(discrete, timed_speed, a));
        if (o.jetrace_only) continue;
        for (bool ccd : {true, false}) {
            double ns = 0;
            long steps = 0;
            bullet_passes(b, ps, timed_speed, a, ccd, &ns, &steps);
            (ccd ? theirs_ccd : theirs).push_back(ns / static_cast<double>(steps));
        }
    }
    if (o.jetrace_only) {  // the step's cost alone: no Bullet, no search for the speed limits
        nlohmann::json j;
        j["scenario"] = "thin_wall";
        j["tick_rate_hz"] = ps.tick_rate_hz;
        j["approaches_per_speed"] = a.phases * a.laterals;
        j["timed_speed_mps"] = timed_speed;
        j["jetrace_mode"] = lab::mode_name(ps);
        j["jetrace_discrete_ns_per_step"] = median(ours_discrete);
        print(j, ours, {});
        return;
    }
    const lab::TunnelLimit lim = lab::tunnelling_limit(def, 10.0, hi, a, ratio);
    const lab::TunnelLimit lim_discrete = lab::tunnelling_limit(discrete, 10.0, hi, a, ratio);
    const auto bullet_limit = [&](bool ccd) {
        return lab::tunnelling_limit([&](double v) { return bullet_passes(b, ps, v, a, ccd); }, 10.0, hi, ratio);
    };
    const lab::TunnelLimit lim_ccd = bullet_limit(true), lim_plain = bullet_limit(false);

    nlohmann::json j;
    j["scenario"] = "thin_wall";
    j["tick_rate_hz"] = ps.tick_rate_hz;
    j["approaches_per_speed"] = a.phases * a.laterals;
    j["timed_speed_mps"] = timed_speed;
    j["probed_max_mps"] = hi;
    j["jetrace_mode"] = lab::mode_name(ps);
    j["jetrace_limit_mps"] = lim.holds_to_mps;
    j["jetrace_discrete_limit_mps"] = lim_discrete.holds_to_mps;
    j["jetrace_discrete_ns_per_step"] = median(ours_discrete);
    j["bullet_ccd"] = "motion threshold 0.5 r, swept sphere radius 0.9 r";
    j["bullet_ccd_limit_mps"] = lim_ccd.holds_to_mps;
    j["bullet_limit_mps"] = lim_plain.holds_to_mps;
    j["bullet_noccd_ns_per_step"] = median(theirs);
    j["bullet_noccd_over_jetrace_discrete"] = median(theirs) / median(ours_discrete);
    j["bullet_noccd_over_jetrace_discrete_by_round"] = median_ratio(theirs, ours_discrete);
    print(j, ours, theirs_ccd);  // the default mode against Bullet with CCD
}

}  // namespace

void add_bullet_options(CLI::App& app, BulletOptions& o) {
    app.add_option("--frames", o.frames, "steps per timed run (idle, driving)")->check(CLI::Range(1, 1000000));
    app.add_option("--repeats", o.repeats, "timed runs per system; medians reported")->check(CLI::Range(1, 100));
    app.add_option("--rate", o.tick_rate_hz, "step rate of both systems (Hz)")->check(CLI::Range(30, 960));
    app.add_flag("--quick", o.quick, "coarse tunnelling search (smoke test)");
    app.add_option("--scenario", o.scenario, "run only this scenario")
        ->check(CLI::IsMember({"idle", "driving", "thin_wall"}));
    app.add_flag("--jetrace-only", o.jetrace_only,
                 "time jetrace only (for callgrind, see docs/ACCURACY.md, and tools/bench_compare.sh); "
                 "thin_wall: without the speed-limit search");
}

int run_bullet(const BulletOptions& o) {
    PhysicsSettings ps;
    ps.tick_rate_hz = o.tick_rate_hz;
    ps.no_progress_s = 3599.0;
    const Track stadium = make_oval(stadium_params());
    const Pose& pole = stadium.spawns.front();
    const auto wanted = [&](const char* name) { return o.scenario.empty() || o.scenario == name; };
    if (wanted("idle")) straight_scenario("idle", Straight{pole.position, Vec3::Zero(), pole.forward, Input{}}, o, ps);
    // Straight B runs from x = 1200 to 0 at z = 300, heading -X.
    const double rest = ps.car_radius_m + ps.resolver_epsilon_m;
    // Frames until 1,000 m are covered from 100 m/s at full thrust (no drag).
    const double a = ps.thrust_mps2, t_straight = (-100.0 + std::sqrt(100.0 * 100.0 + 2.0 * a * 1000.0)) / a;
    const int frames_on_straight = static_cast<int>(t_straight * ps.tick_rate_hz);
    BulletOptions drive = o;
    drive.frames = std::min(o.frames, frames_on_straight);
    if (wanted("driving")) {
        straight_scenario("driving", Straight{Vec3(1150, rest, 300), Vec3(-100, 0, 0), Vec3(-1, 0, 0),
                                              Input::clamped(Input::kMaxThrottle, 0, 0)},
                          drive, ps);
    }
    if (wanted("thin_wall")) thin_wall_scenario(o, ps);
    return 0;
}

}  // namespace jetrace::bench
