// Gathering a car's candidates from the grid (the policy that decides how
// far they reach, gather_reach, is inline in jetrace/core/resolver.hpp).
#include "jetrace/core/resolver.hpp"

#include <algorithm>

namespace jetrace {

namespace {

// Sorts `v`, made of ascending runs, by merging neighbouring runs pass after
// pass (the scratch vectors: the caller's, to keep their capacity).
void merge_runs(std::vector<std::uint32_t>& v, MergeScratch& scratch) {
    std::vector<std::size_t>& bounds = scratch.starts;  // run starts, then the end
    std::vector<std::size_t>& merged = scratch.next_starts;
    bounds.assign(1, 0);
    for (std::size_t i = 1; i < v.size(); ++i) {
        if (v[i] < v[i - 1]) bounds.push_back(i);
    }
    bounds.push_back(v.size());
    while (bounds.size() > 2) {
        scratch.values.resize(v.size());
        merged.assign(1, 0);
        for (std::size_t r = 0; r + 1 < bounds.size(); r += 2) {
            const auto at = [&](std::size_t i) { return v.begin() + static_cast<std::ptrdiff_t>(bounds[i]); };
            const std::size_t last = std::min(r + 2, bounds.size() - 1);
            std::merge(at(r), at(r + 1), at(r + 1), at(last),
                       scratch.values.begin() + static_cast<std::ptrdiff_t>(bounds[r]));
            merged.push_back(bounds[last]);
        }
        v.swap(scratch.values);
        bounds.swap(merged);
    }
}

}  // namespace

void gather_candidates(const TrackQuery& q, const Vec3& center, double radius_m, Candidates& out) {
    out.region = Aabb::around(center, radius_m);
    out.region.min += out.lookahead.cwiseMin(Vec3::Zero());
    out.region.max += out.lookahead.cwiseMax(Vec3::Zero());
    out.triangles.clear();
    out.steps_served = 0;
    out.all = q.broadphase == Broadphase::brute_force;
    if (out.all) {
        out.finish_gather([](std::uint32_t) -> FloatBox { return {}; });
        return;
    }
    if (out.track != &q.track) {  // kept frames belong to one track
        out.frames.clear();
        out.track = &q.track;
    }
    const Vec3 slack(kBoxSlack_m, kBoxSlack_m, kBoxSlack_m);
    const Aabb query{out.region.min - slack, out.region.max + slack};
    // The triangles whose boxes (the grid's, which contain their bounds)
    // reach the query: the grid walks every triangle bucketed in the cells
    // it touches (once per cell) and tests its box, not the triangle (24
    // bytes a triangle, in triangle order, against the triangle's 80), or
    // keeps or drops a chunk of them by the chunk's box.
    std::vector<std::uint32_t>& kept = out.triangles;
    const std::size_t n = q.grid.collect_overlapping(query, kept, 0);
    kept.resize(n);
    // Canonical order: ascending triangle index, the brute-force order. The
    // result of a step then does not depend on which cells were visited or
    // on how large the gathered region was, only on the geometry. Each
    // cell's triangles come in ascending order, so the kept list is a few
    // ascending runs, merged; a triangle met in two cells is kept once.
    merge_runs(kept, out.merge_scratch);
    kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
    out.finish_gather([&](std::uint32_t t) -> const FloatBox& { return q.grid.box(t); });
}

}  // namespace jetrace
