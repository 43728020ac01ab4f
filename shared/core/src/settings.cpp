#include "jetrace/core/settings.hpp"

#include "jetrace/core/math.hpp"

#include <cmath>
#include <sstream>

namespace jetrace {

const char* to_string(Integrator i) {
    switch (i) {
        case Integrator::explicit_euler: return "explicit";
        case Integrator::semi_implicit_euler: return "semi-implicit";
        case Integrator::velocity_verlet: return "verlet";
    }
    return "unknown";
}

const char* to_string(CollisionMode m) {
    switch (m) {
        case CollisionMode::discrete: return "discrete";
        case CollisionMode::swept: return "swept";
    }
    return "unknown";
}

const char* to_string(PushOut p) {
    switch (p) {
        case PushOut::first_contact: return "first-contact";
        case PushOut::each_contact: return "each-contact";
    }
    return "unknown";
}

namespace {
bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }
bool finite_non_negative(double v) { return std::isfinite(v) && v >= 0.0; }
}  // namespace

std::string validate(const PhysicsSettings& s) {
    std::ostringstream err;
    if (s.tick_rate_hz < 10 || s.tick_rate_hz > 10000) err << "tick_rate_hz must be in [10, 10000]; ";
    if (!finite_non_negative(s.gravity_mps2)) err << "gravity_mps2 must be >= 0; ";
    if (!finite_positive(s.car_radius_m) || s.car_radius_m > 100) err << "car_radius_m must be in (0, 100]; ";
    if (!finite_non_negative(s.thrust_mps2)) err << "thrust_mps2 must be >= 0; ";
    if (!finite_non_negative(s.drag_per_m)) err << "drag_per_m must be >= 0; ";
    if (!finite_non_negative(s.brake_mps2)) err << "brake_mps2 must be >= 0; ";
    if (!finite_non_negative(s.steer_rate_radps) || s.steer_rate_radps > 20) err << "steer_rate_radps must be in [0, 20]; ";
    if (!finite_non_negative(s.grip_mps2)) err << "grip_mps2 must be >= 0; ";
    if (!finite_non_negative(s.slide_mps2) || s.slide_mps2 > s.grip_mps2)
        err << "slide_mps2 must be in [0, grip_mps2] (static friction above kinetic); ";
    if (!finite_non_negative(s.align_rate_per_s)) err << "align_rate_per_s must be >= 0; ";
    if (!(s.ride_min_cos >= -1.0 && s.ride_min_cos <= 1.0)) err << "ride_min_cos must be in [-1, 1]; ";
    if (!(s.no_progress_s > 0.0 && s.no_progress_s < 3600.0)) err << "no_progress_s must be in (0, 3600); ";
    if (s.resolver_passes < 1 || s.resolver_passes > 100) err << "resolver_passes must be in [1, 100]; ";
    if (s.push_out != PushOut::first_contact && s.push_out != PushOut::each_contact)
        err << "push_out must be first_contact or each_contact; ";
    if (!finite_non_negative(s.resolver_epsilon_m) || s.resolver_epsilon_m > 0.5) err << "resolver_epsilon_m must be in [0, 0.5]; ";
    if (s.collision_mode != CollisionMode::discrete && s.collision_mode != CollisionMode::swept)
        err << "collision_mode must be discrete or swept; ";
    if (s.sweep_contacts < 1 || s.sweep_contacts > 32) err << "sweep_contacts must be in [1, 32]; ";
    if (!finite_positive(s.contact_skin_m) || s.contact_skin_m <= s.resolver_epsilon_m || s.contact_skin_m > 1.0)
        err << "contact_skin_m must be in (resolver_epsilon_m, 1]; ";
    return err.str();
}

std::uint64_t physics_fingerprint(const PhysicsSettings& s) {
    Fnv1a h;
    h.u32(kPhysicsRevision);
    h.i32(s.tick_rate_hz);
    h.f64(s.gravity_mps2);
    h.f64(s.car_radius_m);
    h.f64(s.thrust_mps2);
    h.f64(s.drag_per_m);
    h.f64(s.brake_mps2);
    h.f64(s.steer_rate_radps);
    h.f64(s.grip_mps2);
    h.f64(s.slide_mps2);
    h.f64(s.align_rate_per_s);
    h.f64(s.ride_min_cos);
    h.f64(s.no_progress_s);
    h.i32(s.resolver_passes);
    h.u8(static_cast<std::uint8_t>(s.push_out));
    h.f64(s.resolver_epsilon_m);
    h.f64(s.contact_skin_m);
    h.u8(static_cast<std::uint8_t>(s.collision_mode));
    h.i32(s.sweep_contacts);
    h.u8(static_cast<std::uint8_t>(s.integrator));
    h.u8(s.quantize_state ? 1 : 0);
    return h.value();
}

}  // namespace jetrace
