#include "jetrace/candidates.hpp"

namespace jetrace {
namespace {

// out[j]: the box around in[j * per] to in[(j + 1) * per - 1] (the last may
// hold fewer).
void boxes_of_runs(const std::vector<Aabb>& in, std::size_t per, std::vector<Aabb>& out) {
    out.clear();
    for (std::size_t k = 0; k < in.size(); k += per) {
        Aabb run = in[k];
        const std::size_t end = std::min(in.size(), k + per);
        for (std::size_t i = k + 1; i < end; ++i) {
            run.min = run.min.cwiseMin(in[i].min);
            run.max = run.max.cwiseMax(in[i].max);
        }
        out.push_back(run);
    }
}

}  // namespace

void Candidates::finish_gather() {
    frames.resize(boxes.size());
    framed.assign(boxes.size(), 0);
    boxes_of_runs(boxes, kRunLength, runs);
    boxes_of_runs(runs, std::size_t{1} << (kGroupShift - kRunShift), groups);
}

}  // namespace jetrace
