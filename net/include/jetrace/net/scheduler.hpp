// DatagramScheduler: the clock-free heart of every network-conditions
// injector (the condition() transport decorator, and the jetrace-netsim UDP
// proxy). The caller owns time: it pushes datagrams with its clock and pops
// the ones due by its clock. Nothing here reads a clock, a socket or a
// global random source, so tests drive it tick by tick.
//
// What happens to a datagram pushed at time `now` (all per flow: a peer, a
// client address...):
//   1. Reliable ones skip 2 and 4-5; their release times never decrease, so
//      they keep their order and are never dropped. With `retransmit_ms` set
//      a reliable one is "lost" with probability `loss` and released a
//      retransmission later instead (the model of a reliable stream, such
//      as TCP: it, and every later reliable one of its flow, waits).
//   2. loss: dropped with probability `loss` (before the link: it costs no
//      bandwidth).
//   3. rate: the flow's link sends `rate_kbps` through a token bucket of
//      `burst_bytes`; a datagram waits (first in, first out) until the
//      bucket holds its size, and an unreliable one that would wait longer
//      than `rate_queue_ms` is dropped instead ("rate-limited").
//   4. duplicate: with probability `duplicate` a copy follows, with its own
//      jitter.
//   5. reorder: with probability `reorder` it is held back until the flow's
//      next unreliable datagram has been queued, then released right behind
//      it (or alone after 100 ms if none comes).
//   Release time = time it leaves the link + latency + uniform [0, jitter].
//
// Every random choice comes from a seeded std::mt19937_64 with a fixed
// mapping to [0, 1), and the same number of draws is taken per datagram
// (1 reliable, 5 unreliable), so a given sequence of calls always produces
// the same outcome.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <unordered_map>
#include <vector>

namespace jetrace::net {

/// Network conditions of one direction of a link.
struct Conditions {
    /// Added one-way delay (unit: ms).
    double latency_ms = 0;
    /// Uniform random extra delay in [0, jitter_ms] (unit: ms).
    double jitter_ms = 0;
    /// Probability that an unreliable datagram is dropped (unit: fraction).
    double loss = 0;
    /// Probability that an unreliable datagram is sent twice (unit: fraction).
    double duplicate = 0;
    /// Probability that an unreliable datagram is held back behind the next
    /// one (unit: fraction).
    double reorder = 0;
    /// Bandwidth of each flow's link (unit: kbit/s of datagram payload;
    /// 0 = unlimited).
    double rate_kbps = 0;
    /// Token bucket size: bytes the link may send at once (unit: bytes).
    double burst_bytes = 3000;
    /// An unreliable datagram that would wait longer than this for the link
    /// is dropped (unit: ms).
    double rate_queue_ms = 100;
    /// Reliable datagrams: 0 = never lost here (the reliability layer is
    /// below, as ENet's under the condition() decorator). Above 0: each send
    /// of one is lost with probability `loss` and resent this much later,
    /// the wait doubling with each loss (at most kMaxResends), as a TCP or
    /// SCTP sender's retransmission (unit: ms).
    double retransmit_ms = 0;
    /// Seed of the random choices.
    std::uint64_t seed = 1;
};

/// One datagram travelling through a DatagramScheduler.
struct ScheduledDatagram {
    /// The flow it belongs to (peer, client address...): reordering, rate and
    /// the order of reliable datagrams are per flow.
    std::uint64_t flow = 0;
    /// Never dropped, duplicated or reordered; keeps its order among the
    /// flow's reliable datagrams.
    bool reliable = false;
    /// The caller's own marker (a channel, "disconnect"...), carried along.
    std::uint32_t tag = 0;
    std::vector<std::uint8_t> data;
};

/// What a scheduler did so far (unit: datagrams).
struct SchedulerStats {
    /// Datagrams pushed (barriers included).
    std::uint64_t offered = 0;
    /// Datagrams handed back by pop_due() (copies included).
    std::uint64_t released = 0;
    /// Unreliable datagrams dropped by `loss`.
    std::uint64_t dropped = 0;
    /// Unreliable datagrams dropped because the link's queue was too long.
    std::uint64_t rate_limited = 0;
    /// Extra copies of unreliable datagrams.
    std::uint64_t duplicated = 0;
    /// Unreliable datagrams released behind the next one of their flow.
    std::uint64_t reordered = 0;
    /// Datagrams (copies included) queued with a release time after their push.
    std::uint64_t delayed = 0;
    /// Resends of reliable datagrams (Conditions::retransmit_ms).
    std::uint64_t retransmitted = 0;
};

class DatagramScheduler {
public:
    /// Out-of-range conditions are clamped (negative or non-finite delays to
    /// 0, probabilities to [0, 1], a non-positive rate to unlimited).
    explicit DatagramScheduler(const Conditions& conditions);

    /// Offers a datagram at the caller's time `now_ms`.
    void push(double now_ms, ScheduledDatagram datagram);
    /// Queues `datagram` behind everything queued or held for its flow, after
    /// the latency; never dropped (e.g. a disconnect after the last packets).
    void push_barrier(double now_ms, ScheduledDatagram datagram);
    /// Appends every datagram due by `now_ms` to `out`, earliest first (ties:
    /// in the order they were queued).
    void pop_due(double now_ms, std::vector<ScheduledDatagram>& out);
    /// When the next datagram becomes due (unit: ms of the caller's clock;
    /// +infinity if nothing is queued or held).
    double next_due_ms() const;
    /// Forgets a flow: everything queued or held for it is discarded.
    void forget(std::uint64_t flow);
    /// Datagrams queued or held.
    std::size_t pending() const;

    const SchedulerStats& stats() const { return stats_; }
    const Conditions& conditions() const { return conditions_; }

    /// A held datagram with no successor is let go alone after this long (unit: ms).
    static constexpr double kMaxHoldMs = 100.0;
    /// The most resends of one reliable datagram (Conditions::retransmit_ms).
    static constexpr int kMaxResends = 6;

private:
    struct Item {
        double release = 0;
        double pushed_at = 0;
        std::uint64_t seq = 0;
        ScheduledDatagram datagram;
    };
    struct Flow {
        double last_reliable = -std::numeric_limits<double>::infinity();
        std::optional<Item> held;
        // Token bucket: `tokens` bytes at time `tokens_at`; the link is busy
        // until `link_free_at` (first in, first out).
        double tokens = 0;
        double tokens_at = -std::numeric_limits<double>::infinity();
        double link_free_at = -std::numeric_limits<double>::infinity();
    };

    static bool later(const Item& a, const Item& b);
    double uniform();
    /// The extra wait of a reliable datagram for its resends (unit: ms).
    double retransmission_wait();
    void enqueue(Item item);
    void release_overdue_held(double now_ms);
    /// When `bytes` pushed at `now_ms` leave the flow's link; nullopt if the
    /// unreliable datagram would wait too long (dropped).
    std::optional<double> through_link(Flow& flow, double now_ms, std::size_t bytes, bool reliable);

    Conditions conditions_;
    std::mt19937_64 rng_;
    std::uint64_t next_seq_ = 0;
    std::vector<Item> queue_;  // a heap ordered by later()
    std::unordered_map<std::uint64_t, Flow> flows_;
    SchedulerStats stats_;
};

}  // namespace jetrace::net
