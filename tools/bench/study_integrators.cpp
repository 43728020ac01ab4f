// Integrators at 30..480 Hz against references (issue 4):
//   ballistic    free flight without drag, against the analytic parabola;
//   flight_drag  free flight with drag, against velocity Verlet at 7,680 Hz;
//   ramp_jump    the full step on a 20 degree ramp, launched at 60 m/s from
//                its lip, against the analytic parabola from the lip;
//   banked_turn  the full step on a cone banked for 32 m/s on a 300 m
//                circle (steering 1/15: yaw rate = speed / radius, no drag,
//                no thrust), against the analytic circle and against the
//                same run at 7,680 Hz.
// All runs without state quantisation (at 7,680 Hz a step's steering is
// below the quaternion quantum); ns per step is the banked turn's full step
// (thread CPU time).
#include "bench/study.hpp"
#include "lab/probes.hpp"

#include <cmath>

namespace jetrace::bench {
namespace {

using lab::Mesh;

constexpr int kRates[] = {30, 60, 120, 240, 480};
constexpr int kReferenceHz = 7680;
constexpr Integrator kIntegrators[] = {Integrator::explicit_euler, Integrator::semi_implicit_euler,
                                       Integrator::velocity_verlet};

PhysicsSettings variant(Integrator in, int hz) {
    PhysicsSettings ps = lab::lab_physics();
    ps.integrator = in;
    ps.tick_rate_hz = hz;
    ps.quantize_state = false;
    return ps;
}

// Quad with its normal on the side of `want`.
void oriented_quad(Mesh& m, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& want) {
    if ((b - a).cross(c - a).dot(want) >= 0) {
        m.quad(a, b, c, d);
    } else {
        m.quad(a, d, c, b);
    }
}

WorldState car_at(const Vec3& p, const Vec3& forward, const Vec3& up, const Vec3& v) {
    WorldState st = make_world(1, 1);
    CarState& car = st.cars[0];
    car.active = true;
    place_car(car, Pose{p, forward, up});
    car.velocity = v;
    return st;
}

// ------------------------------------------------------------ ramp jump
constexpr double kRampDeg = 20.0, kRampSpeed = 60.0, kJump_s = 2.0;

double ramp_jump_error(const PhysicsSettings& ps) {
    const double th = kRampDeg * kPi / 180.0, h = 60.0 * std::tan(th);
    const Vec3 n(-std::sin(th), std::cos(th), 0), d(std::cos(th), std::sin(th), 0);
    Mesh m;
    oriented_quad(m, Vec3(-60, 0, -10), Vec3(-60, 0, 10), Vec3(0, h, 10), Vec3(0, h, -10), n);
    const Scene sc = lab::make_lab_scene(m, ps);
    const Vec3 p0 = Vec3(0, h, 0) + n * (ps.car_radius_m + ps.resolver_epsilon_m);
    WorldState st = car_at(p0, d, n, d * kRampSpeed);
    StepScratch scratch;
    const Input coast{};
    const int steps = static_cast<int>(kJump_s * ps.tick_rate_hz + 0.5);
    for (int i = 0; i < steps; ++i) step(sc, st, {&coast, 1}, scratch);
    const Vec3 exact = p0 + d * kRampSpeed * kJump_s + Vec3(0, -0.5 * ps.gravity_mps2 * kJump_s * kJump_s, 0);
    return (st.cars[0].position - exact).norm();
}

// ---------------------------------------------------------- banked turn
constexpr double kTurnRadius = 300.0;
constexpr int kSteer = 1;

struct Turn {
    Vec3 final_position{0, 0, 0};
    double analytic_error_m = 0;
    double ns_per_step = 0;
};

Turn banked_turn(const PhysicsSettings& base, double seconds) {
    PhysicsSettings ps = base;
    ps.drag_per_m = 0.0;
    const double w = ps.steer_rate_radps * kSteer / Input::kMaxSteer;  // yaw rate (rad/s)
    const double v = w * kTurnRadius;
    const double th = std::atan(v * v / (ps.gravity_mps2 * kTurnRadius));
    const double rest = ps.car_radius_m + ps.resolver_epsilon_m;
    const double rho_s = kTurnRadius + rest * std::sin(th);  // surface radius under the centre line
    Mesh m;
    const int segments = 1440;
    const auto at = [&](double rho, int k) {
        const double phi = 2 * kPi * k / segments;
        return Vec3(rho * std::cos(phi), (rho - rho_s) * std::tan(th), rho * std::sin(phi));
    };
    for (int k = 0; k < segments; ++k) {
        const double phi = 2 * kPi * (k + 0.5) / segments;
        const Vec3 want(-std::sin(th) * std::cos(phi), std::cos(th), -std::sin(th) * std::sin(phi));
        oriented_quad(m, at(kTurnRadius - 30, k), at(kTurnRadius - 30, k + 1), at(kTurnRadius + 30, k + 1),
                      at(kTurnRadius + 30, k), want);
    }
    const Scene sc = lab::make_lab_scene(m, ps);
    const Vec3 n(-std::sin(th), std::cos(th), 0);
    WorldState st = car_at(Vec3(kTurnRadius, rest * std::cos(th), 0), Vec3(0, 0, 1), n, Vec3(0, 0, v));
    StepScratch scratch;
    const Input in = Input::clamped(0, kSteer, 0);
    const int steps = static_cast<int>(seconds * ps.tick_rate_hz + 0.5);
    const CpuTimer timer;
    for (int i = 0; i < steps; ++i) step(sc, st, {&in, 1}, scratch);
    Turn out;
    out.ns_per_step = timer.ns() / steps;
    out.final_position = st.cars[0].position;
    const double t = steps * ps.dt_s();
    const Vec3 exact(kTurnRadius * std::cos(w * t), rest * std::cos(th), kTurnRadius * std::sin(w * t));
    out.analytic_error_m = (out.final_position - exact).norm();
    return out;
}

}  // namespace

namespace {

// spring.csv: energy drift of each integrator on an undamped spring.
void study_spring(const StudyOptions& o) {
    Csv spring_csv(o.out_dir, "spring.csv",
                   {"integrator", "tick_rate_hz", "steps", "max_energy_ratio", "final_energy_ratio"});
    for (Integrator in : kIntegrators) {
        for (int hz : kRates) {
            const lab::SpringRun s = lab::spring(in, hz, 2 * kPi, 100000);
            spring_csv.cell(to_string(in)).cell(hz).cell(100000).cell(s.max_energy_ratio).cell(s.final_energy_ratio);
            spring_csv.end();
        }
    }
}

}  // namespace

std::vector<ParetoPoint> study_integrators(const StudyOptions& o) {
    const double flight_s = 4.0, turn_s = o.quick ? 5.0 : 10.0;
    const Vec3 drag_ref = fly(variant(Integrator::velocity_verlet, kReferenceHz), flight_s);
    const Vec3 ballistic_ref = kFlightStart + kFlightVelocity * flight_s + Vec3(0, -0.5 * 9.81 * flight_s * flight_s, 0);
    const Vec3 turn_ref = banked_turn(variant(Integrator::velocity_verlet, kReferenceHz), turn_s).final_position;

    Csv csv(o.out_dir, "integrators.csv",
            {"scenario", "reference", "integrator", "tick_rate_hz", "error_m", "ns_per_step", "ns_per_sim_s",
             "is_default"});
    // Timing: every variant once per round, rounds repeated, so that load
    // from other processes falls on all variants alike; medians reported.
    std::vector<std::vector<double>> ns(std::size(kIntegrators) * std::size(kRates));
    for (int r = 0; r < o.repeats; ++r) {
        std::size_t k = 0;
        for (Integrator in : kIntegrators) {
            for (int hz : kRates) ns[k++].push_back(banked_turn(variant(in, hz), turn_s).ns_per_step);
        }
    }
    std::vector<ParetoPoint> points;
    const PhysicsSettings defaults;
    std::size_t k = 0;
    for (Integrator in : kIntegrators) {
        for (int hz : kRates) {
            const PhysicsSettings ps = variant(in, hz);
            const Turn turn = banked_turn(ps, turn_s);
            const double ns_step = median(ns[k++]);
            const bool def = in == defaults.integrator && hz == defaults.tick_rate_hz;
            PhysicsSettings no_drag = ps;
            no_drag.drag_per_m = 0.0;
            const double flight_err = (fly(ps, flight_s) - drag_ref).norm();
            const struct {
                const char* scenario;
                const char* reference;
                double error;
            } rows[] = {
                {"ballistic", "analytic", (fly(no_drag, flight_s) - ballistic_ref).norm()},
                {"flight_drag", "verlet_7680Hz", flight_err},
                {"ramp_jump", "analytic", ramp_jump_error(no_drag)},
                {"banked_turn", "analytic", turn.analytic_error_m},
                {"banked_turn", "verlet_7680Hz", (turn.final_position - turn_ref).norm()},
            };
            for (const auto& row : rows) {
                csv.cell(row.scenario).cell(row.reference).cell(to_string(in)).cell(hz).cell(row.error);
                csv.cell(ns_step).cell(ns_step * hz).cell(def).end();
            }
            points.push_back({"integration", std::string(to_string(in)) + "@" + std::to_string(hz) + "Hz",
                              ns_step * hz, flight_err, def});
        }
    }
    study_spring(o);
    return points;
}

}  // namespace jetrace::bench
