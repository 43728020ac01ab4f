// Helpers shared by the jetrace-bench subcommands: timing, medians, CSV
// output, and the free flight of the `integrators` benchmark.
#pragma once

#include "jetrace/core/world.hpp"

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

namespace jetrace::bench {

using Clock = std::chrono::steady_clock;

inline double ns_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
}

/// CPU time of the calling thread (unit: ns). The study times with it: on
/// a shared machine it leaves out the time the thread waits for a core
/// (cache sharing still shows). One call costs a system call, so it brackets
/// whole loops, not single short steps.
double thread_cpu_ns();

/// What an empty CpuTimer measures (median of 1,001 tries, computed once):
/// subtracted where short intervals are summed (unit: ns).
double cpu_timer_overhead_ns();

/// Thread CPU time elapsed since construction.
class CpuTimer {
public:
    CpuTimer() : t0_(thread_cpu_ns()) {}
    double ns() const { return thread_cpu_ns() - t0_; }

private:
    double t0_;
};

double median(std::vector<double> v);

/// Median over rounds of num[i] / den[i]: the ratio of two timings taken
/// side by side in each round, which the machine's drift between rounds
/// does not move (the ratio of the medians can pair a fast round's
/// numerator with a slow round's denominator). Requires equal sizes.
double median_ratio(const std::vector<double>& num, const std::vector<double>& den);

/// One car in free flight (no track contact) for `seconds` from a fixed
/// launch at (0, 500, 0) with velocity (80, 30, 10) m/s; the final position.
Vec3 fly(const PhysicsSettings& ps, double seconds);
inline const Vec3 kFlightStart{0, 500, 0};
inline const Vec3 kFlightVelocity{80, 30, 10};

/// A CSV file: a header line, then rows of cells. Numbers are written with
/// enough digits to round-trip.
class Csv {
public:
    /// Opens `dir/name` for writing; throws std::runtime_error on failure.
    Csv(const std::string& dir, const std::string& name, const std::vector<std::string>& header);
    ~Csv();
    Csv(const Csv&) = delete;
    Csv& operator=(const Csv&) = delete;

    Csv& cell(const std::string& s);
    Csv& cell(const char* s) { return cell(std::string(s)); }
    Csv& cell(double v);
    Csv& cell(long long v);
    Csv& cell(int v) { return cell(static_cast<long long>(v)); }
    Csv& cell(std::size_t v) { return cell(static_cast<long long>(v)); }
    Csv& cell(bool v) { return cell(static_cast<long long>(v ? 1 : 0)); }
    /// Ends the row.
    void end();
    const std::string& path() const { return path_; }

private:
    std::FILE* f_ = nullptr;
    std::string path_;
    bool first_ = true;
};

}  // namespace jetrace::bench
