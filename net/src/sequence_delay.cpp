// SequenceDelayMeter: first arrival to first hand-on of each sequence
// number, per peer (link_conditions.hpp).
#include "jetrace/net/link_conditions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jetrace::net {
namespace {

/// A range ending this far behind the peer's newest number, or this far
/// ahead of it, starts the peer afresh (a new race: input ticks restart at
/// 0). A batch repeats at most 64 inputs and reordering holds one back for
/// at most 100 ms, so an honest range is never this far behind (unit:
/// sequence numbers).
constexpr std::uint32_t kBack = 256;
constexpr std::uint32_t kJumpAhead = 4 * SequenceDelayMeter::kWindow;

bool far_from(std::uint32_t last, std::uint32_t newest) {
    return last + kBack < newest || last > newest + kJumpAhead;
}

}  // namespace

void SequenceDelayMeter::arrived(PeerId peer, double now_ms, std::span<const std::uint8_t> data) {
    const std::optional<SequenceRange> r = extract_(data);
    if (!r || r->last < r->first) return;
    Peer& p = peers_[peer];
    if (p.newest_arrived && far_from(r->last, *p.newest_arrived)) p = Peer{};
    std::uint32_t from = r->first;
    if (p.newest_arrived) from = std::max(from, *p.newest_arrived + 1);
    // Only the newest kWindow numbers of a range can be kept.
    if (r->last - from >= kWindow) from = r->last - (kWindow - 1);
    for (std::uint32_t n = from; n <= r->last && n >= from; ++n) {
        p.first_ms[n % kWindow] = now_ms;
        p.number[n % kWindow] = n;
    }
    if (!p.newest_arrived || r->last > *p.newest_arrived) p.newest_arrived = r->last;
}

void SequenceDelayMeter::delivered(PeerId peer, double now_ms, std::span<const std::uint8_t> data) {
    const std::optional<SequenceRange> r = extract_(data);
    if (!r || r->last < r->first) return;
    const auto it = peers_.find(peer);
    if (it == peers_.end()) return;
    Peer& p = it->second;
    if (p.newest_delivered && far_from(r->last, *p.newest_delivered)) p.newest_delivered.reset();
    std::uint32_t from = r->first;
    if (p.newest_delivered) {
        if (r->last <= *p.newest_delivered) return;
        from = std::max(from, *p.newest_delivered + 1);
        // Numbers between the newest handed on and this range never were.
        if (r->first > *p.newest_delivered + 1) skipped_ += r->first - *p.newest_delivered - 1;
    }
    if (r->last - from >= kWindow) from = r->last - (kWindow - 1);
    for (std::uint32_t n = from; n <= r->last && n >= from; ++n) {
        const std::size_t i = n % kWindow;
        if (p.number[i] == n && p.first_ms[i] >= 0) delays_ms_.push_back(now_ms - p.first_ms[i]);
    }
    p.newest_delivered = r->last;
}

double quantile(std::vector<double> values, double q) {
    if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
    q = std::clamp(std::isfinite(q) ? q : 0.5, 0.0, 1.0);
    std::sort(values.begin(), values.end());
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
    return values[rank == 0 ? 0 : rank - 1];
}

}  // namespace jetrace::net
