// jetrace-bench study: runs every part of the study and writes the Pareto set.
#include "bench/study.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace jetrace::bench {

void write_pareto(const StudyOptions& o, const std::vector<ParetoPoint>& points) {
    Csv csv(o.out_dir, "pareto.csv", {"family", "variant", "cost", "error", "is_default", "on_front"});
    for (const ParetoPoint& p : points) {
        bool dominated = false;
        for (const ParetoPoint& q : points) {
            if (q.family != p.family) continue;
            if (q.cost <= p.cost && q.error <= p.error && (q.cost < p.cost || q.error < p.error)) {
                dominated = true;
                break;
            }
        }
        csv.cell(p.family).cell("\"" + p.variant + "\"").cell(p.cost).cell(p.error).cell(p.is_default);
        csv.cell(!dominated).end();
    }
}

int run_study(const StudyOptions& o) {
    try {
        std::filesystem::create_directories(o.out_dir);
        const auto t0 = Clock::now();
        const auto part = [&](const char* name, auto&& f) {
            const auto t = Clock::now();
            f();
            std::printf("{\"study\":\"%s\",\"seconds\":%.2f}\n", name, ns_since(t) * 1e-9);
            std::fflush(stdout);
        };
        std::vector<ParetoPoint> points;
        part("integrators", [&] { points = study_integrators(o); });
        part("resolver", [&] {
            const std::vector<ParetoPoint> r = study_resolver(o);
            points.insert(points.end(), r.begin(), r.end());
        });
        part("tunnelling", [&] { study_tunnelling(o); });
        part("scale", [&] { study_scale(o); });
        part("pareto", [&] { write_pareto(o, points); });
        std::printf("{\"study\":\"all\",\"out\":\"%s\",\"quick\":%s,\"seconds\":%.2f}\n", o.out_dir.c_str(),
                    o.quick ? "true" : "false", ns_since(t0) * 1e-9);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "study failed: %s\n", e.what());
        return 1;
    }
}

}  // namespace jetrace::bench
