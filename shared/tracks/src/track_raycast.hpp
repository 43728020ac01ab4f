// Rays against track triangles, shared by the OBJ importer and the track
// manifest (gates and spawns placed on the mesh). Internal to jetrace::tracks.
#pragma once

#include "jetrace/core/track.hpp"

#include <vector>

namespace jetrace::detail {

/// Default car radius + the resting gap, as in builtin_tracks.cpp (unit: m).
inline constexpr double kRest_m = 2.5 + 1.0 / 1024.0;

/// Where the line o + t d meets triangle `tri` (Moeller-Trumbore, edges
/// inclusive so shared edges leave no crack): false if it is parallel to the
/// triangle or passes outside it, else its parameter `t` (of any sign).
bool ray_triangle(const Triangle& tri, const Vec3& o, const Vec3& d, double& t);

/// Nearest hit (t >= 0) of the ray o + t d on non-degenerate triangles
/// (Moeller-Trumbore, edges inclusive so shared edges leave no crack).
bool raycast(const std::vector<Triangle>& tris, const Vec3& o, const Vec3& d, double& best_t, Vec3& best_n);

/// The same, giving the index of the triangle hit.
bool raycast_index(const std::vector<Triangle>& tris, const Vec3& o, const Vec3& d, double& best_t,
                   std::size_t& best_index);

enum class Rest { ok, no_surface, bad_forward };

/// The car resting on the first surface along the ray: centre at the hit
/// point plus the surface normal (facing the ray's origin) times kRest_m,
/// up = that normal, forward = `toward` projected onto the surface.
Rest rest_on_surface(const std::vector<Triangle>& tris, const Vec3& origin, const Vec3& dir, const Vec3& toward,
                     Pose& out);

}  // namespace jetrace::detail
