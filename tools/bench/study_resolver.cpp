// The push-out resolver: passes 1..50 x epsilon for the default each-contact
// passes, and for the seed's first-contact passes at epsilon 0 and 1/1024 m
// (issue 4), in the pit whose corner is a fan of 3 x 48 thin triangles
// (lab::corner_mesh):
//   residual penetration  cars driven into the corner at up to 60 m/s from
//                         several headings: deepest end-of-step penetration
//                         and the share of steps ending inside geometry;
//   jitter at rest        a car held in the corner at full throttle: largest
//                         step-to-step movement over its second second;
//   cost                  ns per step of that held car (pushes every step;
//                         thread CPU time).
#include "bench/study.hpp"
#include "lab/probes.hpp"

#include <algorithm>

namespace jetrace::bench {
namespace {

struct Held {
    double jitter_m = 0;
    double ns_per_step = 0;
    double mean_pushes = 0;
};

Held hold_in_corner(const Scene& sc, int steps) {
    const PhysicsSettings& ps = sc.physics;
    const Vec3 dir(-1, 0, -1);
    WorldState st = lab::one_car(Vec3(6, ps.car_radius_m + ps.resolver_epsilon_m, 6), dir.normalized(), Vec3::Zero());
    StepScratch scratch;
    const Input full = Input::clamped(Input::kMaxThrottle, 0, 0);
    Held out;
    Vec3 last = st.cars[0].position;
    long pushes = 0;
    const CpuTimer timer;
    for (int i = 0; i < steps; ++i) {
        step(sc, st, {&full, 1}, scratch);
        pushes += scratch.pushes;
        if (i >= steps / 2) out.jitter_m = std::max(out.jitter_m, (st.cars[0].position - last).norm());
        last = st.cars[0].position;
    }
    out.ns_per_step = timer.ns() / steps;
    out.mean_pushes = static_cast<double>(pushes) / steps;
    return out;
}

}  // namespace

std::vector<ParetoPoint> study_resolver(const StudyOptions& o) {
    const std::vector<int> passes = o.quick ? std::vector<int>{1, 2, 5, 10, 20}
                                            : std::vector<int>{1, 2, 3, 4, 5, 6, 8, 10, 12, 15, 20, 30, 50};
    const double eps_list[] = {0.0, 1.0 / 4096, 1.0 / 1024, 1.0 / 256, 1.0 / 64};
    const int headings = o.quick ? 3 : 9;
    const PhysicsSettings defaults;
    Csv csv(o.out_dir, "resolver.csv",
            {"push_out", "passes", "epsilon_m", "worst_penetration_m", "inside_fraction", "capped_fraction", "jitter_m",
             "mean_pushes", "ns_per_step", "is_default"});
    // Scenes first; then timing rounds over every variant (load from other
    // processes falls on all variants alike); medians reported.
    std::vector<Scene> scenes;
    for (PushOut mode : {PushOut::each_contact, PushOut::first_contact}) {
        for (double eps : eps_list) {
            if (mode == PushOut::first_contact && eps != 0.0 && eps != defaults.resolver_epsilon_m) continue;
            for (int p : passes) {
                PhysicsSettings ps = lab::lab_physics();
                ps.push_out = mode;
                ps.resolver_passes = p;
                ps.resolver_epsilon_m = eps;
                scenes.push_back(lab::make_lab_scene(lab::corner_mesh(), ps));
            }
        }
    }
    std::vector<std::vector<double>> ns(scenes.size());
    for (int r = 0; r < o.repeats; ++r) {
        for (std::size_t k = 0; k < scenes.size(); ++k) {
            ns[k].push_back(hold_in_corner(scenes[k], 2 * scenes[k].physics.tick_rate_hz).ns_per_step);
        }
    }
    std::vector<ParetoPoint> points;
    for (std::size_t k = 0; k < scenes.size(); ++k) {
        const PhysicsSettings& ps = scenes[k].physics;
        const lab::CornerRun run = lab::drive_into_corners(ps, 60.0, headings, 1.0);
        const Held held = hold_in_corner(scenes[k], 2 * ps.tick_rate_hz);
        const bool def = ps.push_out == defaults.push_out && ps.resolver_passes == defaults.resolver_passes &&
                         ps.resolver_epsilon_m == defaults.resolver_epsilon_m;
        const double worst = std::max(0.0, run.worst_penetration_m);
        csv.cell(to_string(ps.push_out)).cell(ps.resolver_passes).cell(ps.resolver_epsilon_m).cell(worst);
        csv.cell(static_cast<double>(run.inside_steps) / run.steps);
        csv.cell(static_cast<double>(run.capped_steps) / run.steps).cell(held.jitter_m).cell(held.mean_pushes);
        csv.cell(median(ns[k])).cell(def).end();
        char name[64];
        std::snprintf(name, sizeof name, "%s, %d passes, eps %g", to_string(ps.push_out), ps.resolver_passes,
                      ps.resolver_epsilon_m);
        points.push_back({"resolver", name, median(ns[k]), worst, def});
    }
    return points;
}

}  // namespace jetrace::bench
