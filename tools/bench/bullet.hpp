// jetrace-bench bullet: the same track and scenarios in Bullet (a sphere on a
// btBvhTriangleMeshShape in a btDiscreteDynamicsWorld, same step rate,
// deactivation off) and in jetrace, in one run. Built only when Bullet is
// found (pkg-config `bullet`).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace jetrace::bench {

struct BulletOptions {
    /// Steps per timed run of the idle and driving scenarios (unit: steps).
    int frames = 1200;
    /// Timed runs per system and scenario, alternating; medians reported (unit: runs).
    int repeats = 5;
    /// Step rate of both systems (unit: Hz).
    int tick_rate_hz = 120;
    /// Coarser tunnelling search (for the smoke test).
    bool quick = false;
    /// Only this scenario ("idle", "driving", "thin_wall"; "" = all).
    std::string scenario;
    /// Idle and driving: time jetrace's runs only (no Bullet), e.g. to count
    /// instructions per step under callgrind (docs/ACCURACY.md).
    bool jetrace_only = false;
};

void add_bullet_options(CLI::App& app, BulletOptions& o);
int run_bullet(const BulletOptions& o);

}  // namespace jetrace::bench
