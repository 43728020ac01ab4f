// Tick durations for jetrace-server's exit figures in constant memory: a
// histogram with logarithmic bins 1 % wide from 1 us to 100 s, so that the
// median and the 99th percentile come out within 1 % however long the server
// runs (storing every sample grew the process by about 1 KiB a second).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace jetrace::server {

class TickTimes {
public:
    TickTimes() : bins_(kBins, 0) {}

    /// Records `count` ticks that took `ms` each (unit: ms).
    void add(double ms, std::uint64_t count = 1) {
        bins_[bin(ms)] += count;
        count_ += count;
    }
    /// The p-quantile, p in [0, 1] (unit: ms; 0 if nothing was recorded).
    double percentile(double p) const {
        if (count_ == 0) return 0.0;
        const auto rank = static_cast<std::uint64_t>(std::clamp(p, 0.0, 1.0) * static_cast<double>(count_ - 1) + 0.5);
        std::uint64_t seen = 0;
        for (std::size_t i = 0; i < bins_.size(); ++i) {
            seen += bins_[i];
            if (seen > rank) return value(i);
        }
        return value(bins_.size() - 1);
    }
    std::uint64_t count() const { return count_; }

    /// Smallest duration told apart from 0, and the bin width (unit: ms, ratio).
    static constexpr double kMinMs = 1e-3;
    static constexpr double kRatio = 1.01;

private:
    // Bin 0: up to kMinMs; bin i >= 1: (kMinMs * kRatio^(i-1), kMinMs * kRatio^i]; the last: above 100 s too.
    static constexpr std::size_t kBins = 1 + 1852;

    static std::size_t bin(double ms) {
        if (!(ms > kMinMs)) return 0;  // also NaN
        const double i = std::ceil(std::log(ms / kMinMs) / std::log(kRatio));
        return static_cast<std::size_t>(std::min(i, static_cast<double>(kBins - 1)));
    }
    // The geometric middle of bin i.
    static double value(std::size_t i) {
        if (i == 0) return kMinMs;
        return kMinMs * std::pow(kRatio, static_cast<double>(i) - 0.5);
    }

    std::vector<std::uint64_t> bins_;
    std::uint64_t count_ = 0;
};

}  // namespace jetrace::server
