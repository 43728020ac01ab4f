// Per-IP token buckets on the caller's clock: the WebRTC transport's limits
// on STUN requests and DTLS handshake datagrams. Bounded: at most kMaxIps
// addresses are remembered (beyond, a new address is refused), and those
// idle long enough to be full again are forgotten.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>

namespace jetrace::rtc::detail {

/// A token bucket on the caller's clock.
struct TokenBucket {
    double tokens = 0;
    std::uint64_t last_ms = 0;
    bool fresh = true;
    /// Refills at `per_s` up to `burst`, then takes one token if there is one.
    bool take(std::uint64_t now_ms, double per_s, double burst);
};

class RateLimits {
public:
    static constexpr std::size_t kMaxIps = 16384;
    RateLimits(double per_s, double burst) : per_s_(per_s), burst_(burst) {}
    /// Takes a token of `ip`'s bucket; false if it has none (or no room for a new address).
    bool allow(const std::string& ip, std::uint64_t now_ms);
    /// Forgets buckets idle over 10 s (every 5 s at most).
    void prune(std::uint64_t now_ms);

private:
    double per_s_, burst_;
    std::map<std::string, TokenBucket> buckets_;
    std::uint64_t pruned_ms_ = 0;
};

}  // namespace jetrace::rtc::detail
