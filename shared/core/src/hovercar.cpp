#include "jetrace/core/hovercar.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace jetrace {

Input Input::clamped(int throttle, int steer, int brake) {
    Input in;
    in.throttle = static_cast<std::int8_t>(std::clamp(throttle, 0, kMaxThrottle));
    in.steer = static_cast<std::int8_t>(std::clamp(steer, -kMaxSteer, kMaxSteer));
    in.brake = static_cast<std::uint8_t>(brake != 0 ? 1 : 0);
    return in;
}

std::uint16_t Input::pack() const {
    return static_cast<std::uint16_t>((throttle & 0xF) | (((steer + kMaxSteer) & 0x1F) << 4) | ((brake & 1) << 9));
}

Input Input::unpack(std::uint16_t bits) {
    return clamped(bits & 0xF, static_cast<int>((bits >> 4) & 0x1F) - kMaxSteer, (bits >> 9) & 1);
}

Quat orientation_from(const Vec3& forward, const Vec3& up) {
    // Columns are the images of local X (right-handed: up x forward), Y, Z.
    Eigen::Matrix3d m;
    m.col(0) = up.cross(forward);
    m.col(1) = up;
    m.col(2) = forward;
    Quat q(m);
    q.normalize();
    return q;
}

void place_car(CarState& car, const Pose& pose) {
    car.position = pose.position;
    car.velocity = Vec3::Zero();
    car.orientation = orientation_from(pose.forward, pose.up);
    quantize_car(car);
}

namespace {

// Shortest projection of a unit axis into a surface that still gives a
// direction along it.
constexpr double kMinTangent = 1e-6;

// Whether `memo` holds the unit form of the stored orientation `stored`.
bool holds_unit_of(const SupportMemo& memo, const Quat& stored) {
    // same_bits(), written out: through the call GCC's link-time inlining
    // chooses differently elsewhere.
    return memo.unit_valid && std::memcmp(memo.stored.coeffs().data(), stored.coeffs().data(), 4 * sizeof(double)) == 0;
}

// The unit form of the car's stored orientation, and its up, in `memo`:
// found again with the same stored bits, the last ones are kept (and so is
// the support frame worked out for them).
const SupportMemo& unit_frame(const Quat& stored, SupportMemo& memo) {
    if (holds_unit_of(memo, stored)) return memo;
    memo.stored = stored;
    memo.unit = normalized_near_unit(stored);
    memo.up = axis_y(memo.unit);
    memo.unit_valid = true;
    memo.frame_valid = false;
    return memo;
}

// The supporting normal among `contacts` for a car with unit orientation
// `q` and up `up`, and its forward along it (see SupportMemo), into `f`.
// `kept`: `f` already holds the frame worked out for this `q`, valid if
// the normal is the same too.
// Always inline: out of line, its call and the memo's reloads cost more
// than its hit path.
[[gnu::always_inline]] inline void support_frame(const Contacts& contacts, const Quat& q, const Vec3& up,
                                                 double min_cos, bool kept, SupportMemo& f) {
    const int i = contacts.support(up, min_cos);
    if (i < 0) {
        f.grounded = false;
        f.frame_valid = false;
        return;
    }
    const Vec3& normal = contacts.normal[i];
    if (kept && f.frame_valid && std::memcmp(f.normal.data(), normal.data(), 3 * sizeof(double)) == 0) return;
    const Vec3 fwd = axis_z(q);
    const Vec3 tangent_forward = fwd - normal * fwd.dot(normal);
    const Vec3 tangent_up = up - normal * up.dot(normal);
    constexpr double min2 = kMinTangent * kMinTangent;
    const bool along_forward = tangent_forward.squaredNorm() > min2;
    // No usable direction along the surface: treat as airborne.
    f.grounded = along_forward || tangent_up.squaredNorm() > min2;
    f.forward = along_forward ? normalized_or(tangent_forward, {}, kMinTangent)
                              : normalized_or(tangent_up, Vec3::Zero(), kMinTangent);
    f.normal = normal;
    // Kept only for the memo's own unit orientation (not a steered one).
    f.frame_valid = kept;
}

// The unit orientation q, with up `up`, turned about that up over one step
// of `dt` (unit: s): axis_angle(up, angle) * q, the half angle's sine and
// cosine kept in `memo` for the next step with the same angle.
Quat steered(const PhysicsSettings& s, double dt, const Input& input, const Quat& q, const Vec3& up,
             SupportMemo& memo) {
    // Positive steer turns right: a negative rotation about up.
    const double angle = -static_cast<double>(input.steer) / Input::kMaxSteer * s.steer_rate_radps * dt;
    if (!memo.turn_valid || std::bit_cast<std::uint64_t>(angle) != std::bit_cast<std::uint64_t>(memo.turn_rad)) {
        const double h = 0.5 * angle;
        memo.turn_rad = angle;
        memo.turn_half_sin = det_sin(h);
        memo.turn_half_cos = det_cos(h);
        memo.turn_valid = true;
    }
    const double sn = memo.turn_half_sin;
    return Quat(memo.turn_half_cos, up.x() * sn, up.y() * sn, up.z() * sn) * q;
}

// Sideways friction over one step of `dt` (unit: s; seed: static threshold
// above the kinetic decrement).
void sideways_friction(const PhysicsSettings& s, double dt, const Vec3& right, CarState& car) {
    const double lateral = car.velocity.dot(right);
    const double grip = s.grip_mps2 * dt;
    if (std::abs(lateral) <= grip) {
        car.velocity -= right * lateral;  // grip
    } else {
        const double slide = s.slide_mps2 * dt;
        car.velocity -= right * (lateral > 0 ? slide : -slide);  // drift
    }
}

void brake(const PhysicsSettings& s, double dt, const SupportMemo& f, CarState& car) {
    // Slow the along-surface velocity by brake*dt, never reversing it.
    const Vec3 along = car.velocity - f.normal * car.velocity.dot(f.normal);
    const double speed2 = along.squaredNorm();
    if (speed2 <= 0.0) return;
    const double speed = std::sqrt(speed2);
    const double dv = s.brake_mps2 * dt;
    car.velocity -= speed <= dv ? along : along * (dv / speed);
}

bool is_zero(const Vec3& v) { return v.x() == 0.0 && v.y() == 0.0 && v.z() == 0.0; }

}  // namespace

void apply_controls_and_forces(const PhysicsSettings& s, const Contacts& contacts, const Input& input, CarState& car,
                               SupportMemo& memo) {
    const double dt = s.dt_s();
    const SupportMemo& u = unit_frame(car.orientation, memo);
    if (input.steer != 0) {
        const Quat q = steered(s, dt, input, u.unit, u.up, memo);
        car.orientation = q;
        support_frame(contacts, q, axis_y(q), s.ride_min_cos, false, memo);
    } else {
        support_frame(contacts, u.unit, u.up, s.ride_min_cos, true, memo);
    }
    const SupportMemo& f = memo;

    Vec3 accel(0.0, -s.gravity_mps2, 0.0);
    if (f.grounded) {
        if (input.throttle > 0) accel += f.forward * (s.thrust_mps2 * input.throttle / Input::kMaxThrottle);
        // Normal force: the surface cancels the part of the acceleration that
        // pushes into it (so a car at rest stays exactly at rest).
        const double into = accel.dot(f.normal);
        if (into < 0.0) accel -= f.normal * into;
    }
    // Quadratic drag, always (on the speed before this step's forces).
    const double speed2 = car.velocity.squaredNorm();
    car.velocity += accel * dt;
    if (speed2 > 0.0) car.velocity -= car.velocity * std::min(1.0, s.drag_per_m * std::sqrt(speed2) * dt);

    // Brake and friction act on motion: a car exactly at rest has none.
    if (f.grounded && !is_zero(car.velocity)) {
        if (input.brake) brake(s, dt, f, car);
        sideways_friction(s, dt, f.forward.cross(f.normal), car);
    }
}

void apply_controls_and_forces(const PhysicsSettings& s, const Contacts& contacts, const Input& input, CarState& car) {
    SupportMemo memo;
    apply_controls_and_forces(s, contacts, input, car, memo);
}

void integrate(const PhysicsSettings& s, const Vec3& v0, CarState& car) {
    const double dt = s.dt_s();
    switch (s.integrator) {
        case Integrator::explicit_euler: car.position += v0 * dt; break;
        case Integrator::semi_implicit_euler: car.position += car.velocity * dt; break;
        case Integrator::velocity_verlet: car.position += (v0 + car.velocity) * (0.5 * dt); break;
    }
}

void align_to_contacts(const PhysicsSettings& s, const Contacts& contacts, CarState& car, const SupportMemo& memo) {
    // The controls kept the unit orientation in `memo` unless they steered
    // (then the rounding at the end of this step gives the next controls
    // other bits: not kept).
    const bool kept = holds_unit_of(memo, car.orientation);
    const Quat q = kept ? memo.unit : car.unit_orientation();
    const Vec3 up = kept ? memo.up : axis_y(q);
    const int i = contacts.support(up, s.ride_min_cos);
    if (i < 0) return;  // in the air: keep the orientation (the seed's tilted jumps)
    if (same(up, contacts.normal[i])) return;  // already aligned: no turn (a car on a flat floor)
    const double t = std::min(1.0, s.align_rate_per_s * s.dt_s());
    const Quat arc = shortest_arc(up, contacts.normal[i]);
    car.orientation = nlerp_from_identity(arc, t) * q;
}

void align_to_contacts(const PhysicsSettings& s, const Contacts& contacts, CarState& car) {
    align_to_contacts(s, contacts, car, SupportMemo{});
}

void quantize_motion(CarState& car) { quantize_motion(car.position, car.velocity); }

void quantize_orientation(CarState& car) {
    // Unit to rounding after a turn, or already quantised (within 1e-4 of
    // unit; the next step normalises it): quantise it as it is.
    Quat q = car.orientation;
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // one representative: w >= 0
    quantize(q, kQuatBits);
    car.orientation = q;
}

}  // namespace jetrace
