// Discrete push-out against the swept (continuous) test (issue 4): the
// highest speed at which a car sliding into a zero-thickness wall never ends
// a step beyond it, over a grid of approach phases and offsets, per step
// rate, for both collision modes.
#include "bench/study.hpp"
#include "lab/probes.hpp"

#include <cmath>

namespace jetrace::bench {

void study_tunnelling(const StudyOptions& o) {
    const lab::Approach approach = o.quick ? lab::Approach{8, 2} : lab::Approach{16, 4};
    const double ratio = o.quick ? 1.1 : 1.03;
    const double hi_mps = 4000.0;
    Csv csv(o.out_dir, "tunnelling.csv",
            {"mode", "tick_rate_hz", "holds_to_mps", "first_pass_mps", "probed_max_mps", "r_over_dt_mps",
             "top_speed_mps", "is_default"});
    const PhysicsSettings defaults;
    for (bool swept : {false, true}) {
        for (int hz : {30, 60, 120, 240, 480}) {
            PhysicsSettings ps = lab::lab_physics();
            ps.tick_rate_hz = hz;
            lab::set_swept(ps, swept);
            const Scene sc = lab::make_lab_scene(lab::thin_wall_mesh(), ps);
            const lab::TunnelLimit lim = lab::tunnelling_limit(sc, 10.0, hi_mps, approach, ratio);
            const bool def = hz == defaults.tick_rate_hz && std::string(lab::mode_name(ps)) == lab::mode_name(defaults);
            csv.cell(lab::mode_name(ps)).cell(hz).cell(lim.holds_to_mps).cell(lim.first_pass_mps).cell(hi_mps);
            csv.cell(ps.car_radius_m / ps.dt_s()).cell(std::sqrt(ps.thrust_mps2 / ps.drag_per_m)).cell(def).end();
        }
    }
}

}  // namespace jetrace::bench
