// jetrace-bench study: the speed-against-accuracy study of issue 4. Each
// part writes one or more CSV files into the output directory; charts.sh
// turns them into the charts of docs/ACCURACY.md.
#pragma once

#include "bench/common.hpp"

#include <string>
#include <vector>

namespace jetrace::bench {

struct StudyOptions {
    /// Directory the CSV files go to (created if missing).
    std::string out_dir = "study";
    /// Fewer variants and shorter runs (the whole study in under a minute).
    bool quick = false;
    /// Runs per timed variant; the median is reported (unit: runs).
    int repeats = 3;
};

/// One variant as a point of the Pareto chart.
struct ParetoPoint {
    std::string family;   // "integration" or "resolver"
    std::string variant;  // e.g. "verlet@120Hz"
    double cost = 0;      // integration: ns per simulated second; resolver: ns per step
    double error = 0;     // integration: m; resolver: m of residual penetration
    bool is_default = false;
};

/// integrators.csv (error against analytic and 7,680 Hz references, ns per
/// step) and spring.csv (energy per integrator on an undamped spring).
std::vector<ParetoPoint> study_integrators(const StudyOptions& o);
/// resolver.csv: passes x epsilon: residual penetration, jitter, ns per step.
std::vector<ParetoPoint> study_resolver(const StudyOptions& o);
/// tunnelling.csv: thin-wall limit per step rate and collision mode.
void study_tunnelling(const StudyOptions& o);
/// grid_cell.csv, track_size.csv, cars.csv.
void study_scale(const StudyOptions& o);
/// pareto.csv: every point with its family's front marked.
void write_pareto(const StudyOptions& o, const std::vector<ParetoPoint>& points);

/// Runs every part; returns the process exit code.
int run_study(const StudyOptions& o);

}  // namespace jetrace::bench
