// DatagramScheduler: delay queue, loss, duplication, reordering and a token
// bucket per flow, on the caller's clock (see scheduler.hpp).
#include "jetrace/net/scheduler.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace jetrace::net {
namespace {

double clamp_fraction(double p) { return std::isfinite(p) ? std::clamp(p, 0.0, 1.0) : 0.0; }
double clamp_nonnegative(double v) { return std::isfinite(v) ? std::max(v, 0.0) : 0.0; }

}  // namespace

DatagramScheduler::DatagramScheduler(const Conditions& conditions) : rng_(conditions.seed) {
    conditions_.latency_ms = clamp_nonnegative(conditions.latency_ms);
    conditions_.jitter_ms = clamp_nonnegative(conditions.jitter_ms);
    conditions_.loss = clamp_fraction(conditions.loss);
    conditions_.duplicate = clamp_fraction(conditions.duplicate);
    conditions_.reorder = clamp_fraction(conditions.reorder);
    conditions_.rate_kbps = clamp_nonnegative(conditions.rate_kbps);
    conditions_.burst_bytes = clamp_nonnegative(conditions.burst_bytes);
    conditions_.rate_queue_ms = clamp_nonnegative(conditions.rate_queue_ms);
    conditions_.retransmit_ms = clamp_nonnegative(conditions.retransmit_ms);
    conditions_.seed = conditions.seed;
}

bool DatagramScheduler::later(const Item& a, const Item& b) {
    if (a.release != b.release) return a.release > b.release;
    return a.seq > b.seq;
}

double DatagramScheduler::uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }

double DatagramScheduler::retransmission_wait() {
    if (conditions_.retransmit_ms <= 0) return 0;
    double wait = 0;
    double timeout = conditions_.retransmit_ms;
    for (int sends = 0; sends < kMaxResends && uniform() < conditions_.loss; ++sends) {
        ++stats_.retransmitted;
        wait += timeout;
        timeout *= 2;
    }
    return wait;
}

void DatagramScheduler::enqueue(Item item) {
    item.seq = next_seq_++;
    if (item.release > item.pushed_at) ++stats_.delayed;
    queue_.push_back(std::move(item));
    std::push_heap(queue_.begin(), queue_.end(), later);
}

std::optional<double> DatagramScheduler::through_link(Flow& flow, double now_ms, std::size_t bytes, bool reliable) {
    const double rate = conditions_.rate_kbps / 8.0;  // bytes per ms
    if (rate <= 0) return now_ms;
    const double burst = conditions_.burst_bytes;
    const auto level_at = [&](double t) {
        if (!std::isfinite(flow.tokens_at)) return burst;  // a new flow starts with a full bucket
        return std::min(burst, flow.tokens + (t - flow.tokens_at) * rate);
    };
    const double start = std::max(now_ms, flow.link_free_at);
    const double level = level_at(start);
    // A datagram larger than the bucket waits for a full bucket and leaves a debt.
    const double need = std::min(static_cast<double>(bytes), burst);
    const double leave = level >= need ? start : start + (need - level) / rate;
    if (!reliable && leave - now_ms > conditions_.rate_queue_ms) return std::nullopt;
    flow.tokens = level + (leave - start) * rate - static_cast<double>(bytes);
    flow.tokens_at = leave;
    flow.link_free_at = leave;
    return leave;
}

void DatagramScheduler::push(double now_ms, ScheduledDatagram datagram) {
    ++stats_.offered;
    Flow& flow = flows_[datagram.flow];
    Item item;
    item.pushed_at = now_ms;
    const std::size_t bytes = datagram.data.size();
    item.datagram = std::move(datagram);

    if (item.datagram.reliable) {
        const double jitter = uniform() * conditions_.jitter_ms;
        const double leave = *through_link(flow, now_ms, bytes, true);
        const double resent = retransmission_wait();
        item.release = std::max(leave + conditions_.latency_ms + jitter + resent, flow.last_reliable);
        flow.last_reliable = item.release;
        enqueue(std::move(item));
        return;
    }

    const double u_loss = uniform();
    const double u_duplicate = uniform();
    const double u_reorder = uniform();
    const double jitter = uniform() * conditions_.jitter_ms;
    const double copy_jitter = uniform() * conditions_.jitter_ms;
    if (u_loss < conditions_.loss) {
        ++stats_.dropped;
        return;
    }
    const std::optional<double> leave = through_link(flow, now_ms, bytes, false);
    if (!leave) {
        ++stats_.rate_limited;
        return;
    }
    const double base = *leave + conditions_.latency_ms;
    item.release = base + jitter;
    std::optional<Item> copy;
    if (u_duplicate < conditions_.duplicate) {
        ++stats_.duplicated;
        copy = item;
        copy->release = base + copy_jitter;
    }
    if (flow.held) {
        // The held datagram goes right behind this one.
        Item held = std::move(*flow.held);
        flow.held.reset();
        held.release = std::max(held.release, item.release);
        enqueue(std::move(item));
        if (copy) enqueue(std::move(*copy));
        ++stats_.reordered;
        enqueue(std::move(held));
    } else if (u_reorder < conditions_.reorder) {
        flow.held = std::move(item);
        if (copy) enqueue(std::move(*copy));
    } else {
        enqueue(std::move(item));
        if (copy) enqueue(std::move(*copy));
    }
}

void DatagramScheduler::push_barrier(double now_ms, ScheduledDatagram datagram) {
    ++stats_.offered;
    Flow& flow = flows_[datagram.flow];
    if (flow.held) {
        enqueue(std::move(*flow.held));
        flow.held.reset();
    }
    Item item;
    item.pushed_at = now_ms;
    item.release = std::max(now_ms + conditions_.latency_ms, flow.last_reliable);
    for (const Item& queued : queue_) {
        if (queued.datagram.flow == datagram.flow) item.release = std::max(item.release, queued.release);
    }
    item.datagram = std::move(datagram);
    enqueue(std::move(item));
}

void DatagramScheduler::release_overdue_held(double now_ms) {
    for (auto& [id, flow] : flows_) {
        if (flow.held && now_ms >= flow.held->release + kMaxHoldMs) {
            enqueue(std::move(*flow.held));
            flow.held.reset();
        }
    }
}

void DatagramScheduler::pop_due(double now_ms, std::vector<ScheduledDatagram>& out) {
    release_overdue_held(now_ms);
    while (!queue_.empty() && queue_.front().release <= now_ms) {
        std::pop_heap(queue_.begin(), queue_.end(), later);
        out.push_back(std::move(queue_.back().datagram));
        queue_.pop_back();
        ++stats_.released;
    }
}

double DatagramScheduler::next_due_ms() const {
    double next = queue_.empty() ? std::numeric_limits<double>::infinity() : queue_.front().release;
    for (const auto& [id, flow] : flows_) {
        if (flow.held) next = std::min(next, flow.held->release + kMaxHoldMs);
    }
    return next;
}

void DatagramScheduler::forget(std::uint64_t flow) {
    flows_.erase(flow);
    const auto removed = std::erase_if(queue_, [&](const Item& item) { return item.datagram.flow == flow; });
    if (removed > 0) std::make_heap(queue_.begin(), queue_.end(), later);
}

std::size_t DatagramScheduler::pending() const {
    std::size_t n = queue_.size();
    for (const auto& [id, flow] : flows_) n += flow.held ? 1 : 0;
    return n;
}

}  // namespace jetrace::net
