// jetrace::server::TickTimes: percentiles within 1 % of the exact ones, in
// constant memory.
#include "jetrace/server/tick_times.hpp"

#include "support/test_seed.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace {

using jetrace::server::TickTimes;

double exact(std::vector<double> v, double p) {
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5)];
}

TEST(TickTimes, PercentilesWithinOnePercentOfExact) {
    std::mt19937_64 rng(jetrace::test::test_seed(5));
    std::lognormal_distribution<double> tick_ms(-2.0, 1.0);  // ~0.1 ms, a long tail
    TickTimes t;
    std::vector<double> all;
    for (int i = 0; i < 200000; ++i) {
        const double ms = tick_ms(rng);
        all.push_back(ms);
        t.add(ms);
    }
    EXPECT_EQ(t.count(), all.size());
    for (const double p : {0.0, 0.1, 0.5, 0.9, 0.99, 0.999, 1.0}) {
        const double want = std::max(exact(all, p), TickTimes::kMinMs);
        EXPECT_NEAR(t.percentile(p) / want, 1.0, 0.0101) << "p=" << p;
    }
}

TEST(TickTimes, EmptyRepeatedAndOutOfRange) {
    TickTimes t;
    EXPECT_EQ(t.percentile(0.5), 0.0);
    t.add(2.0, 99);
    t.add(1e9);    // above the last bin: counted there
    t.add(-1.0);   // and below the first
    EXPECT_EQ(t.count(), 101u);
    EXPECT_NEAR(t.percentile(0.5), 2.0, 0.02);
    EXPECT_GT(t.percentile(1.0), 99000.0);
    EXPECT_EQ(t.percentile(0.0), TickTimes::kMinMs);
}

}  // namespace
