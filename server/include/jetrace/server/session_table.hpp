// The server's sessions: every connection (a Client), the slot each player
// holds, the slots held for players who dropped (the reconnect grace), and
// the reconnect tokens, live and spent. Lookup by peer, slot and token; no
// messages are sent here (RaceServer decides what each change means).
#pragma once

#include "jetrace/net/transport.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/server/input_queue.hpp"

#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace jetrace::server {

using ReconnectToken = std::array<std::uint8_t, proto::kTokenBytes>;

/// One connection, and once welcomed its player.
struct Client {
    net::PeerId peer = 0;
    bool greeted = false;
    std::string name;
    /// Hello.name as sent (a reconnect must send the same).
    std::string hello_name;
    ReconnectToken reconnect_token{};
    int slot = -1;
    bool spectating = false;
    /// Welcomed as an observer (Hello.observe): no slot (-1), no car, no
    /// reconnect token; it gets snapshots, RaceStatus and Results.
    bool observer = false;
    std::uint64_t connected_us = 0;
    InputQueue inputs;
    std::uint32_t acked_snapshot = proto::kNoTick;
    /// Track file bytes sent to this connection (TrackChunk; unit: bytes).
    std::uint64_t track_bytes_sent = 0;
    /// Anomalies already logged for this client (bits of RaceServer's Anomaly).
    std::uint8_t logged_anomalies = 0;
    /// What a new race or a new connection starts without: inputs and
    /// the acknowledged snapshot.
    void reset_link_state() {
        inputs.reset();
        acked_snapshot = proto::kNoTick;
    }
};

/// A dropped player's client, kept for a reconnect until `until_us`.
struct HeldClient {
    Client client;
    std::uint64_t until_us = 0;
};

class SessionTable {
public:
    explicit SessionTable(int max_players);

    // Connections.
    Client& connect(net::PeerId peer, std::uint64_t now_us);
    Client* find(net::PeerId peer);
    /// Takes the client out of the table (its slot, if any, stays as it is
    /// until seat(), hold() or free_slot()).
    Client take(net::PeerId peer);
    const std::map<net::PeerId, Client>& clients() const { return clients_; }
    /// Ordered by peer: deterministic iteration.
    std::map<net::PeerId, Client>& clients() { return clients_; }
    /// Greeted clients but observers (connected players and spectators).
    int players() const;
    /// Greeted observers.
    int observers() const;
    /// Greeted clients but observers.
    std::vector<net::PeerId> player_peers() const;
    /// Connections without a Hello for more than `timeout_us` by `now_us`.
    std::vector<net::PeerId> silent(std::uint64_t now_us, std::uint64_t timeout_us) const;

    // Slots.
    /// The lowest free slot, or -1.
    int first_free_slot() const;
    /// `c` (in the table) plays in c.slot.
    void seat(const Client& c);
    /// Frees `slot` (its player left for good).
    void free_slot(int slot);
    /// The connected or held client in `slot`, or nullptr.
    const Client* owner_of(int slot) const;
    /// The connected client driving `slot`, or nullptr (free or held).
    Client* driver_of(std::size_t slot);
    const Client* driver_of(std::size_t slot) const;

    // The reconnect grace.
    void hold(Client&& c, std::uint64_t until_us);
    const std::map<int, HeldClient>& held() const { return held_; }
    /// Takes out a held client whose grace ended by `now_us`; false if none.
    bool take_expired(std::uint64_t now_us, Client& out);

    // Reconnect tokens.
    /// Who owns `token`: a held slot, or a live connection the server has
    /// not yet seen drop (the client noticed first).
    struct TokenOwner {
        Client* client = nullptr;
        int held_slot = -1;               // >= 0: held
        net::PeerId live_peer = kNoPeer;  // != kNoPeer: live
    };
    TokenOwner owner_of_token(std::span<const std::uint8_t> token);
    /// Takes the owner out of the table (held or live).
    Client take(const TokenOwner& owner);
    /// Remembers why `token` is void.
    void retire(const ReconnectToken& token, std::string why);
    /// Why `token` is void, or "" if it was never seen.
    std::string retired_reason(std::span<const std::uint8_t> token) const;

    static constexpr net::PeerId kNoPeer = 0xFFFFFFFFu;

private:
    /// Spent reconnect tokens remembered to refuse them with a clear reason.
    static constexpr std::size_t kRetiredTokens = 256;
    /// In slot_peer_: the slot's player dropped and may reconnect (held_).
    static constexpr net::PeerId kHeldPeer = 0xFFFFFFFEu;

    std::map<net::PeerId, Client> clients_;
    std::vector<net::PeerId> slot_peer_;  // per slot, or kNoPeer / kHeldPeer
    std::map<int, HeldClient> held_;      // by slot
    std::deque<std::pair<ReconnectToken, std::string>> retired_;
};

}  // namespace jetrace::server
