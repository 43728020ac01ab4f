// Welcome.physics: every PhysicsSettings field, in declaration order.
#include "physics_wire.hpp"

#include <cassert>
#include <cmath>

namespace jetrace::proto {

flatbuffers::Offset<wire::PhysicsSettings> encode_physics(flatbuffers::FlatBufferBuilder& b, const PhysicsSettings& s) {
    assert(s.tick_rate_hz >= 1 && s.tick_rate_hz <= 0xFFFF && s.resolver_passes >= 0 && s.sweep_contacts >= 0);
    return wire::CreatePhysicsSettings(
        b, static_cast<std::uint16_t>(s.tick_rate_hz), s.gravity_mps2, s.car_radius_m, s.thrust_mps2, s.drag_per_m,
        s.brake_mps2, s.steer_rate_radps, s.grip_mps2, s.slide_mps2, s.align_rate_per_s, s.ride_min_cos,
        s.no_progress_s, static_cast<std::uint16_t>(s.resolver_passes), static_cast<std::uint8_t>(s.push_out),
        s.resolver_epsilon_m, s.contact_skin_m, static_cast<std::uint8_t>(s.collision_mode),
        static_cast<std::uint16_t>(s.sweep_contacts), static_cast<std::uint8_t>(s.integrator), s.quantize_state);
}

bool decode_physics(const wire::PhysicsSettings& t, PhysicsSettings& out, std::string& why) {
    PhysicsSettings s;
    s.tick_rate_hz = t.tick_rate_hz();
    s.gravity_mps2 = t.gravity_mps2();
    s.car_radius_m = t.car_radius_m();
    s.thrust_mps2 = t.thrust_mps2();
    s.drag_per_m = t.drag_per_m();
    s.brake_mps2 = t.brake_mps2();
    s.steer_rate_radps = t.steer_rate_radps();
    s.grip_mps2 = t.grip_mps2();
    s.slide_mps2 = t.slide_mps2();
    s.align_rate_per_s = t.align_rate_per_s();
    s.ride_min_cos = t.ride_min_cos();
    s.no_progress_s = t.no_progress_s();
    s.resolver_passes = t.resolver_passes();
    s.resolver_epsilon_m = t.resolver_epsilon_m();
    s.contact_skin_m = t.contact_skin_m();
    s.sweep_contacts = t.sweep_contacts();
    s.quantize_state = t.quantize_state();
    for (double v : {s.gravity_mps2, s.car_radius_m, s.thrust_mps2, s.drag_per_m, s.brake_mps2, s.steer_rate_radps,
                     s.grip_mps2, s.slide_mps2, s.align_rate_per_s, s.ride_min_cos, s.no_progress_s,
                     s.resolver_epsilon_m, s.contact_skin_m}) {
        if (!std::isfinite(v)) {
            why = "a setting is not a finite number";
            return false;
        }
    }
    if (t.push_out() > static_cast<std::uint8_t>(PushOut::each_contact)) {
        why = "unknown push_out";
        return false;
    }
    if (t.collision_mode() > static_cast<std::uint8_t>(CollisionMode::swept)) {
        why = "unknown collision_mode";
        return false;
    }
    if (t.integrator() > static_cast<std::uint8_t>(Integrator::velocity_verlet)) {
        why = "unknown integrator";
        return false;
    }
    s.push_out = static_cast<PushOut>(t.push_out());
    s.collision_mode = static_cast<CollisionMode>(t.collision_mode());
    s.integrator = static_cast<Integrator>(t.integrator());
    // The core's own rules, so whatever decodes is a PhysicsSettings that
    // step() and encode_physics() accept.
    if (const std::string bad = validate(s); !bad.empty()) {
        why = bad;
        return false;
    }
    out = s;
    return true;
}

}  // namespace jetrace::proto
