// The client's link to the server: the transport (and, with a Connector, the
// new ones after a drop), the Hello, the join and reconnect retries and the
// welcome timeout, and why the link closed (docs/PROTOCOL.md, "The client's
// states" and "Reconnecting"). It knows nothing of worlds or snapshots.
#pragma once

#include "jetrace/client/client_config.hpp"
#include "jetrace/net/transport.hpp"
#include "jetrace/proto/close_code.hpp"
#include "jetrace/proto/messages.hpp"

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace jetrace::client {

/// Opens a new connection to the server (nullptr: cannot right now).
using Connector = std::function<std::unique_ptr<net::Transport>()>;

enum class LinkState : std::uint8_t {
    /// The first connection coming up; no Hello out yet.
    connecting,
    /// Hello out (a join), no Welcome yet.
    waiting_welcome,
    /// Welcomed: a slot, no world yet.
    in_lobby,
    /// Welcomed, and a snapshot started the world (stays so across races).
    racing,
    /// Dropped with a slot to take back: a new connection is due.
    reconnect_due,
    /// A new connection is under way; once up, its Hello carries the
    /// reconnect token.
    reconnecting,
    /// Nothing was admitted (no Hello reached the server): a new connection
    /// to join again is due.
    rejoin_due,
    /// A new connection to join again is under way (a plain Hello once up).
    rejoining,
    closed,
};

/// The client's state (docs/PROTOCOL.md, "The client's states"): the
/// link's, its four reconnect states folded into one.
enum class ClientState : std::uint8_t { connecting, waiting_welcome, in_lobby, racing, reconnecting, closed };

class Link {
public:
    /// Over the caller's transport; no reconnects.
    Link(const ClientConfig& config, net::Transport& transport);
    /// Opens a connection through `connect` now (closed if it cannot), and
    /// new ones after a drop.
    Link(const ClientConfig& config, Connector connect);

    LinkState state() const { return state_; }
    ClientState client_state() const;
    /// Dropped and not connected again yet (any of the reconnect states).
    bool reconnecting() const;
    /// Waiting for a new connection: the events still queued came from the
    /// dead one.
    bool connection_due() const { return state_ == LinkState::reconnect_due || state_ == LinkState::rejoin_due; }
    /// The transport of the connection now (nullptr: none open).
    net::Transport* transport() const { return transport_; }

    /// Gives up once the retry window is over, opens the due connection,
    /// then services the transport into `events`. False: no transport.
    bool poll(std::uint64_t now_us, std::vector<net::Event>& events);
    /// A transport's connected or disconnected event.
    void on_connection_event(const net::Event& e);
    /// Leaves if no Welcome came within the welcome timeout.
    void check_welcome_timeout();
    void flush();

    /// Whether a Welcome is expected now (else it is ignored).
    bool awaits_welcome() const { return state_ == LinkState::waiting_welcome || reconnecting(); }
    /// Takes the Welcome: in_lobby. True if it gave back the slot of a
    /// dropped connection (a reconnect, not a join).
    bool on_welcome(const proto::Welcome& w);
    void on_refuse(const proto::Refuse& r);
    /// Kept until the disconnect that follows, which then closes the link
    /// (or joins again if the server never got the Hello).
    void on_goodbye(const proto::Goodbye& g);
    /// The first snapshot of a race started the world.
    void start_racing();

    /// Says goodbye (on the wire always `left`; `why` stays here) and closes.
    void leave(const std::string& reason, proto::CloseCode why);
    const std::string& close_reason() const { return close_reason_; }
    std::uint16_t close_code() const { return close_code_; }
    const std::vector<std::uint8_t>& reconnect_token() const { return reconnect_token_; }
    double rtt_ms() const { return transport_ ? transport_->peer_stats(0).rtt_ms : 0.0; }
    double rtt_variance_ms() const { return transport_ ? transport_->peer_stats(0).rtt_variance_ms : 0.0; }
    /// Traffic of every connection so far.
    net::Totals totals() const;

private:
    void close(const std::string& reason, proto::CloseCode why);
    void send_hello();
    /// `code`: what the disconnect carried (net::Event::close_code).
    void on_disconnected(std::uint16_t code);
    /// Closes with the server's Goodbye if one came, else with the pre-Hello
    /// cap's refusal if that ended the last attempt, else "disconnected".
    void close_on_drop();
    /// Closes once the retry window `window_s` is over.
    void give_up(bool rejoin, double window_s);
    /// The pause before the next attempt: reconnect_retry_s; after refusals
    /// by the pre-Hello cap, doubled for each further one in a row (up to 4
    /// times it) and spread at random over 0.5 to 1.5 times that, so that
    /// clients refused together do not come back together.
    std::uint64_t retry_delay_us();
    bool may_reconnect() const;
    bool may_rejoin() const;
    /// Replaces the dead connection with a new one.
    void open_due_connection();

    ClientConfig config_;
    Connector connector_;
    std::unique_ptr<net::Transport> owned_;  // with a Connector
    net::Transport* transport_ = nullptr;
    net::Totals past_totals_;  // of the connections before this one
    LinkState state_ = LinkState::connecting;
    std::uint64_t now_us_ = 0;
    std::uint64_t dropped_at_us_ = 0;  // start of the retry window
    std::uint64_t next_attempt_us_ = 0;
    std::uint64_t hello_sent_us_ = 0;
    int slot_ = -1;  // of the Welcome: the car a reconnect takes back
    std::vector<std::uint8_t> reconnect_token_;
    std::optional<proto::Goodbye> goodbye_;  // the server's, until the disconnect
    /// Attempts in a row the server's pre-Hello cap refused (net::
    /// kPreHelloRefusal): the last one ended so when > 0.
    int cap_refusals_ = 0;
    /// The connection now came up (its ENet `connected` event).
    bool up_ = false;
    std::minstd_rand jitter_{std::random_device{}()};
    std::string close_reason_;
    std::uint16_t close_code_ = 0;
};

}  // namespace jetrace::client
