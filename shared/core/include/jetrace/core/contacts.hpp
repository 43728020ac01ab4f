// The contact normals gathered around a car.
#pragma once

#include "jetrace/core/math.hpp"

namespace jetrace {

/// Fixed-capacity list of unit contact normals (pointing from the surface
/// to the car's centre). Beyond kMax, further contacts are dropped in a
/// fixed order (the candidate order), which keeps stepping deterministic.
struct Contacts {
    static constexpr int kMax = 16;
    Vec3 normal[kMax];
    int count = 0;

    void clear() { count = 0; }
    void add(const Vec3& n) {
        if (count < kMax) normal[count++] = n;
    }
    bool empty() const { return count == 0; }
    /// Index of the supporting normal closest in direction to `up` (largest
    /// dot), or -1. A normal supports if its dot with `up` or with world up
    /// is at least `min_cos`.
    int support(const Vec3& up, double min_cos) const {
        int best = -1;
        double best_dot = -2.0;
        for (int i = 0; i < count; ++i) {
            const double d = normal[i].dot(up);
            if (d < min_cos && normal[i].y() < min_cos) continue;
            if (d > best_dot) {
                best_dot = d;
                best = i;
            }
        }
        return best;
    }
};

}  // namespace jetrace
