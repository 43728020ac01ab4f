#include "route_line.hpp"

#include <algorithm>
#include <cmath>

namespace jetrace::detail {

namespace {

double seg_len(const RoutePoint& a, const RoutePoint& b) { return std::hypot(b.x - a.x, b.z - a.z); }

Vec3 direction(const RoutePoint& a, const RoutePoint& b) {
    return Vec3(b.x - a.x, 0.0, b.z - a.z) / seg_len(a, b);
}

}  // namespace

bool RouteLine::build(const std::vector<RoutePoint>& points, std::string& error) {
    points_.clear();
    for (const RoutePoint& p : points) {
        if (points_.empty() || seg_len(points_.back(), p) > 1e-6) points_.push_back(p);
    }
    while (points_.size() > 1 && !(seg_len(points_.back(), points_.front()) > 1e-6)) points_.pop_back();
    if (points_.size() < 3) {
        error = "the route needs at least 3 distinct points (x, z)";
        return false;
    }
    cumulative_.assign(1, 0.0);
    for (std::size_t i = 0; i < points_.size(); ++i) {
        cumulative_.push_back(cumulative_.back() + seg_len(points_[i], points_[(i + 1) % points_.size()]));
    }
    return true;
}

void RouteLine::at(double u, RoutePoint& p, Vec3& tangent) const {
    const double len = length();
    u = std::fmod(u, len);
    if (u < 0) u += len;
    std::size_t i = static_cast<std::size_t>(std::upper_bound(cumulative_.begin(), cumulative_.end(), u) -
                                             cumulative_.begin());
    i = std::clamp<std::size_t>(i, 1, points_.size()) - 1;
    const RoutePoint& a = points_[i];
    const RoutePoint& b = points_[(i + 1) % points_.size()];
    const double f = std::clamp((u - cumulative_[i]) / (cumulative_[i + 1] - cumulative_[i]), 0.0, 1.0);
    p.x = a.x + (b.x - a.x) * f;
    p.z = a.z + (b.z - a.z) * f;
    p.y.reset();
    if (a.y && b.y) p.y = *a.y + (*b.y - *a.y) * f;
    tangent = direction(a, b);
}

double RouteLine::project(const RoutePoint& q, Vec3& tangent) const {
    double best = -1, best_u = 0;
    for (std::size_t i = 0; i < points_.size(); ++i) {
        const RoutePoint& a = points_[i];
        const RoutePoint& b = points_[(i + 1) % points_.size()];
        const double len = cumulative_[i + 1] - cumulative_[i];
        const double f = std::clamp(((q.x - a.x) * (b.x - a.x) + (q.z - a.z) * (b.z - a.z)) / (len * len), 0.0, 1.0);
        const double d = std::hypot(a.x + (b.x - a.x) * f - q.x, a.z + (b.z - a.z) * f - q.z);
        if (best < 0 || d < best) {
            best = d;
            best_u = cumulative_[i] + f * len;
            tangent = direction(a, b);
        }
    }
    return best_u;
}

}  // namespace jetrace::detail
