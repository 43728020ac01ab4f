// Network conditions on both directions of a transport's links, applied at
// this end (a server's): condition_link() wraps a Transport so that what it
// sends waits, and may be lost, on the way out, and what it receives waits,
// and may be lost, before it is handed on. One DatagramScheduler a
// direction, one flow a peer, on the caller's clock given to service().
//
// This is how jetrace-server puts jetrace-netsim's conditions on browser
// players (--web-link), whose transports sit above a stack this process
// cannot reach into (SCTP in the data channel, TCP under a WebSocket): the
// delivery model says what a loss becomes at this level.
#pragma once

#include "jetrace/net/scheduler.hpp"
#include "jetrace/net/transport.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

namespace jetrace::net {

/// What a loss on the link becomes above the transport.
enum class Delivery : std::uint8_t {
    /// Separate datagrams (ENet, the WebRTC data channel): a lost unreliable
    /// one is gone; a reliable one is resent after Conditions::retransmit_ms
    /// (0: never lost), and later reliable ones of the peer wait behind it.
    datagrams,
    /// One ordered stream for both channels (a WebSocket's TCP connection):
    /// every message is reliable; a lost one is resent after
    /// Conditions::retransmit_ms and every message after it waits for it
    /// (head-of-line blocking).
    stream,
};

/// Both directions of every peer's link, seen from this end.
struct LinkConditions {
    /// What this end sends (a server's snapshots).
    Conditions outgoing;
    /// What this end receives (a client's inputs).
    Conditions incoming;
    Delivery delivery = Delivery::datagrams;
};

/// Watches the datagrams a conditioned link receives: when each reached
/// this end, and when it was handed on (unit: ms of the caller's clock).
class LinkObserver {
public:
    virtual ~LinkObserver() = default;
    virtual void arrived(PeerId peer, double now_ms, std::span<const std::uint8_t> data) = 0;
    virtual void delivered(PeerId peer, double now_ms, std::span<const std::uint8_t> data) = 0;
};

/// Wraps `inner`: both directions conditioned (see the top of this file).
/// Connection events pass at once; a peer's disconnection is handed on
/// after everything already received from it. `observer` (may be null)
/// must outlive the transport.
std::unique_ptr<Transport> condition_link(std::unique_ptr<Transport> inner, const LinkConditions& link,
                                          LinkObserver* observer = nullptr);

/// A range of sequence numbers one datagram carries (first..last, inclusive).
struct SequenceRange {
    std::uint32_t first = 0;
    std::uint32_t last = 0;
};

/// Measures the delay of sequence numbers through a conditioned link: from
/// the first time a number (a client's input tick) reaches this end in any
/// datagram, lost ones included, to the first time one carrying it is
/// handed on. With redundancy (every input batch repeats the inputs not yet
/// acknowledged) a lost datagram costs the interval to the next one; on a
/// stream it costs the retransmission. `extract` reads the range a datagram
/// carries (nullopt: none, e.g. not an input batch).
class SequenceDelayMeter final : public LinkObserver {
public:
    using Extract = std::function<std::optional<SequenceRange>(std::span<const std::uint8_t>)>;
    explicit SequenceDelayMeter(Extract extract) : extract_(std::move(extract)) {}

    void arrived(PeerId peer, double now_ms, std::span<const std::uint8_t> data) override;
    void delivered(PeerId peer, double now_ms, std::span<const std::uint8_t> data) override;

    /// Every delay measured so far, in the order measured (unit: ms).
    const std::vector<double>& delays_ms() const { return delays_ms_; }
    /// Numbers that arrived and were never handed on (a later one was first).
    std::uint64_t skipped() const { return skipped_; }

    /// First-arrival times kept per peer (unit: sequence numbers).
    static constexpr std::uint32_t kWindow = 1024;

private:
    struct Peer {
        std::vector<double> first_ms = std::vector<double>(kWindow, -1.0);
        std::vector<std::uint32_t> number = std::vector<std::uint32_t>(kWindow, 0);
        std::optional<std::uint32_t> newest_arrived;
        std::optional<std::uint32_t> newest_delivered;
    };
    Extract extract_;
    std::unordered_map<PeerId, Peer> peers_;
    std::vector<double> delays_ms_;
    std::uint64_t skipped_ = 0;
};

/// The `q` quantile (0..1) of `values` by the nearest rank (NaN if empty).
double quantile(std::vector<double> values, double q);

}  // namespace jetrace::net
