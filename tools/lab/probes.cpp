#include "lab/probes.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace::lab {

// ---------------------------------------------------------------- tunnelling

Mesh thin_wall_mesh() {
    Mesh m;
    m.floor(-400, 400, -24, 24, 24);
    m.wall_x(0.0, 40.0, 20.0, 4.0);
    return m;
}

Vec3 approach_start(const PhysicsSettings& ps, double speed_mps, const Approach& a, int phase, int lateral) {
    const double rest = ps.car_radius_m + ps.resolver_epsilon_m;
    // Phase 0: where a push-out off the wall leaves a car (r + epsilon from
    // it, the closest a car can be without touching); then back by fractions
    // of one step's travel. Laterals: across one 4 m square of the wall.
    const double x0 = -rest - speed_mps * ps.dt_s() * phase / a.phases;
    const double z0 = 4.0 * (lateral + 0.5) / a.laterals;
    return Vec3(x0, rest, z0);
}

bool passes_through(const Scene& scene, double speed_mps, const Approach& a) {
    const Input coast{};
    StepScratch scratch;
    for (int p = 0; p < a.phases; ++p) {
        for (int l = 0; l < a.laterals; ++l) {
            const Vec3 start = approach_start(scene.physics, speed_mps, a, p, l);
            WorldState st = one_car(start, Vec3(1, 0, 0), Vec3(speed_mps, 0, 0));
            for (int i = 0; i < kApproachSteps; ++i) {
                step(scene, st, {&coast, 1}, scratch);
                if (st.cars[0].position.x() > 0.0) return true;
            }
        }
    }
    return false;
}

TunnelLimit tunnelling_limit(const Scene& scene, double lo_mps, double hi_mps, const Approach& a, double ratio,
                             double tol_mps) {
    return tunnelling_limit([&](double v) { return passes_through(scene, v, a); }, lo_mps, hi_mps, ratio, tol_mps);
}

TunnelLimit tunnelling_limit(const std::function<bool(double)>& passes, double lo_mps, double hi_mps, double ratio,
                             double tol_mps) {
    TunnelLimit out;
    double hold = 0.0, fail = 0.0;
    for (double v = lo_mps; v <= hi_mps * (1 + 1e-12); v *= ratio) {
        if (passes(v)) {
            fail = v;
            break;
        }
        hold = v;
    }
    if (fail == 0.0) {
        out.holds_to_mps = hold;
        return out;
    }
    while (fail - hold > tol_mps) {
        const double mid = 0.5 * (hold + fail);
        (passes(mid) ? fail : hold) = mid;
    }
    out.holds_to_mps = hold;
    out.first_pass_mps = fail;
    return out;
}

// -------------------------------------------------------------------- spring

SpringRun spring(Integrator integrator, int tick_rate_hz, double omega_radps, long steps) {
    PhysicsSettings ps;
    ps.integrator = integrator;
    ps.tick_rate_hz = tick_rate_hz;
    const double dt = ps.dt_s(), w2 = omega_radps * omega_radps;
    CarState car;
    car.position = Vec3(1, 0, 0);
    const auto energy = [&] { return 0.5 * car.velocity.squaredNorm() + 0.5 * w2 * car.position.squaredNorm(); };
    const double e0 = energy();
    SpringRun out;
    for (long i = 0; i < steps; ++i) {
        const Vec3 v0 = car.velocity;
        car.velocity += -w2 * car.position * dt;
        integrate(ps, v0, car);
        out.max_energy_ratio = std::max(out.max_energy_ratio, energy() / e0);
    }
    out.final_energy_ratio = energy() / e0;
    return out;
}

// --------------------------------------------------------------------- seams

namespace {
struct Trace {
    std::vector<double> y, speed;
};

Trace slide(const PhysicsSettings& ps, double cell_m, double speed_mps, double heading_deg, int steps,
            double drop_m, double vy_mps) {
    const double h = heading_deg * kPi / 180.0;
    const Vec3 dir(det_cos(h), 0, det_sin(h));
    const double len = speed_mps * steps * ps.dt_s() + 20.0;
    Mesh m;
    m.floor(-20, 20 + len * dir.x(), -20 + std::min(0.0, len * dir.z()), 20 + std::max(0.0, len * dir.z()), cell_m);
    const Scene sc = make_lab_scene(m, ps);
    const double rest = ps.car_radius_m + ps.resolver_epsilon_m;
    WorldState st = one_car(Vec3(0, rest + drop_m, 0), dir, dir * speed_mps + Vec3(0, vy_mps, 0));
    StepScratch scratch;
    const Input coast{};
    Trace t;
    for (int i = 0; i < steps; ++i) {
        step(sc, st, {&coast, 1}, scratch);
        t.y.push_back(st.cars[0].position.y());
        t.speed.push_back(st.cars[0].velocity.norm());
    }
    return t;
}
}  // namespace

SeamRun slide_over_seams(const PhysicsSettings& ps, double cell_m, double speed_mps, double heading_deg,
                         double seconds, double drop_m, double vy_mps) {
    const int steps = static_cast<int>(seconds * ps.tick_rate_hz + 0.5);
    const Trace fine = slide(ps, cell_m, speed_mps, heading_deg, steps, drop_m, vy_mps);
    const Trace ref = slide(ps, 1.0e6, speed_mps, heading_deg, steps, drop_m, vy_mps);
    SeamRun out;
    out.steps = steps;
    for (int i = 0; i < steps; ++i) {
        out.max_excursion_m = std::max(out.max_excursion_m, std::abs(fine.y[i] - ref.y[i]));
        out.max_speed_change_mps = std::max(out.max_speed_change_mps, std::abs(fine.speed[i] - ref.speed[i]));
    }
    out.reference_speed_mps = ref.speed.back();
    return out;
}

// -------------------------------------------------------------------- corner

namespace {
// Splits the rectangle with corner `o` and edges `u`, `w` into `n` triangles
// fanned from `o` (so `n` thin triangles meet at that corner), each with its
// normal on the side of `inward`.
void fan(Mesh& m, const Vec3& o, const Vec3& u, const Vec3& w, int n, const Vec3& inward) {
    std::vector<Vec3> rim;  // far boundary: o+u -> o+u+w -> o+w
    for (int k = 0; k <= n / 2; ++k) rim.push_back(o + u + w * (static_cast<double>(k) / (n / 2)));
    for (int k = 1; k <= n / 2; ++k) rim.push_back(o + w + u * (1.0 - static_cast<double>(k) / (n / 2)));
    for (std::size_t k = 0; k + 1 < rim.size(); ++k) {
        Vec3 b = rim[k], c = rim[k + 1];
        if ((b - o).cross(c - o).dot(inward) < 0) std::swap(b, c);
        const auto base = static_cast<std::uint32_t>(m.vertices.size());
        m.vertices.insert(m.vertices.end(), {o, b, c});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
}
}  // namespace

Mesh corner_mesh() {
    Mesh m;
    const double s = 40.0, h = 20.0;
    const Vec3 o(0, 0, 0);
    fan(m, o, Vec3(s, 0, 0), Vec3(0, 0, s), 48, Vec3(0, 1, 0));  // floor
    fan(m, o, Vec3(0, h, 0), Vec3(0, 0, s), 48, Vec3(1, 0, 0));  // wall x = 0
    fan(m, o, Vec3(s, 0, 0), Vec3(0, h, 0), 48, Vec3(0, 0, 1));  // wall z = 0
    fan(m, Vec3(s, 0, s), Vec3(-s, 0, 0), Vec3(0, h, 0), 48, Vec3(0, 0, -1));  // wall z = s
    fan(m, Vec3(s, 0, s), Vec3(0, 0, -s), Vec3(0, h, 0), 48, Vec3(-1, 0, 0));  // wall x = s
    return m;
}

CornerRun drive_into_corners(const PhysicsSettings& ps, double max_speed_mps, int headings, double seconds) {
    const Scene sc = make_lab_scene(corner_mesh(), ps);
    const double r = ps.car_radius_m, rest = r + ps.resolver_epsilon_m;
    const int steps = static_cast<int>(seconds * ps.tick_rate_hz + 0.5);
    const Input full = Input::clamped(Input::kMaxThrottle, 0, 0);
    CornerRun out;
    StepScratch scratch;
    for (int hi = 0; hi < headings; ++hi) {
        // Towards the fanned corner at the origin, +-40 degrees about the diagonal.
        const double a = kPi * (1.25 + (headings > 1 ? (hi / (headings - 1.0) - 0.5) * (80.0 / 180.0) : 0.0));
        const Vec3 dir(det_cos(a), 0, det_sin(a));
        for (double f : {0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0}) {
            const double v = f * max_speed_mps;
            WorldState st = one_car(Vec3(20, rest, 20), dir, dir * v + Vec3(0, -0.2 * v, 0));
            for (int i = 0; i < steps; ++i) {
                step(sc, st, {&full, 1}, scratch);
                const double d = min_distance(sc.track, st.cars[0].position);
                const bool inside = d < r - 1e-6;
                ++out.steps;
                out.capped_steps += scratch.capped;
                out.inside_steps += inside ? 1 : 0;
                out.inside_uncapped_steps += inside && scratch.capped == 0 ? 1 : 0;
                out.worst_penetration_m = std::max(out.worst_penetration_m, r - d);
                out.max_pushes = std::max(out.max_pushes, scratch.pushes);
                out.max_passes = std::max(out.max_passes, scratch.max_passes);
            }
        }
    }
    return out;
}

}  // namespace jetrace::lab
