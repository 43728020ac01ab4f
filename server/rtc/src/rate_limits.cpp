#include "rate_limits.hpp"

#include <algorithm>

namespace jetrace::rtc::detail {

bool TokenBucket::take(std::uint64_t now_ms, double per_s, double burst) {
    if (fresh) {
        fresh = false;
        tokens = burst;
        last_ms = now_ms;
    }
    tokens = std::min(burst, tokens + static_cast<double>(now_ms - std::min(now_ms, last_ms)) * per_s / 1000.0);
    last_ms = now_ms;
    if (tokens < 1) return false;
    tokens -= 1;
    return true;
}

bool RateLimits::allow(const std::string& ip, std::uint64_t now_ms) {
    auto it = buckets_.find(ip);
    if (it == buckets_.end()) {
        if (buckets_.size() >= kMaxIps) return false;
        it = buckets_.emplace(ip, TokenBucket{}).first;
    }
    return it->second.take(now_ms, per_s_, burst_);
}

void RateLimits::prune(std::uint64_t now_ms) {
    if (now_ms < pruned_ms_ + 5000) return;
    pruned_ms_ = now_ms;
    std::erase_if(buckets_, [&](const auto& b) { return now_ms > b.second.last_ms + 10000; });
}

}  // namespace jetrace::rtc::detail
