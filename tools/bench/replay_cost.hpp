// jetrace-bench replay: what replay format version 2 costs, on an offline
// AI race (default: 8 cars, 5 minutes of stadium): bytes per tick against
// version 1's fixed layout, the recorder's share of the server's tick
// (stepping with and without writing, alternated, median of the per-round
// ratios), signing, and the wall time of verify(). One JSON object.
#pragma once

#include <string>

namespace jetrace::bench {

struct ReplayCostOptions {
    /// (unit: cars).
    int cars = 8;
    /// Simulated race length (unit: s).
    double seconds = 300;
    /// Rounds of each timing; medians are reported.
    int repeats = 5;
    /// Where the replays are written ("" = the temporary directory).
    std::string dir;
};

int run_replay_cost(const ReplayCostOptions& o);

}  // namespace jetrace::bench
