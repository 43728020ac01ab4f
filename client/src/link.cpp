#include "jetrace/client/link.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace jetrace::client {

namespace {

std::uint64_t to_us(double s) { return static_cast<std::uint64_t>(s * 1e6); }

std::string server_said(const proto::Goodbye& g) { return "server: " + g.reason; }

static_assert(net::kPreHelloRefusal == static_cast<std::uint16_t>(proto::CloseCode::refused_pre_hello_cap),
              "the transport's refusal is the protocol's close code");

/// Doublings of the pause between attempts after refusals in a row (the
/// pause goes 1, 2, 4 times reconnect_retry_s, then stays; each spread).
constexpr int kMaxBackoffDoublings = 2;

constexpr const char* kCapRefusal =
    "refused: too many connections from this address are waiting for their Hello (the server's pre-Hello cap)";

}  // namespace

Link::Link(const ClientConfig& config, net::Transport& transport) : config_(config), transport_(&transport) {}

Link::Link(const ClientConfig& config, Connector connect) : config_(config), connector_(std::move(connect)) {
    owned_ = connector_ ? connector_() : nullptr;
    transport_ = owned_.get();
    if (!transport_) close("cannot open a connection", proto::CloseCode::local_connection_lost);
}

bool Link::reconnecting() const {
    return state_ == LinkState::reconnect_due || state_ == LinkState::reconnecting ||
           state_ == LinkState::rejoin_due || state_ == LinkState::rejoining;
}

ClientState Link::client_state() const {
    switch (state_) {
        case LinkState::connecting: return ClientState::connecting;
        case LinkState::waiting_welcome: return ClientState::waiting_welcome;
        case LinkState::in_lobby: return ClientState::in_lobby;
        case LinkState::racing: return ClientState::racing;
        case LinkState::closed: return ClientState::closed;
        default: return ClientState::reconnecting;
    }
}

net::Totals Link::totals() const {
    net::Totals t = past_totals_;
    if (transport_) {
        const net::Totals now = transport_->totals();
        t.bytes_sent += now.bytes_sent;
        t.bytes_received += now.bytes_received;
        t.packets_sent += now.packets_sent;
        t.packets_received += now.packets_received;
    }
    return t;
}

void Link::close(const std::string& reason, proto::CloseCode why) {
    if (state_ == LinkState::closed) return;
    state_ = LinkState::closed;
    close_reason_ = reason;
    close_code_ = static_cast<std::uint16_t>(why);
    spdlog::info("{}: closed: {}", config_.name, reason);
}

void Link::leave(const std::string& reason, proto::CloseCode why) {
    if (state_ == LinkState::closed) return;
    if (!transport_) return close(reason, why);
    transport_->send(0, net::Channel::reliable,
                     proto::encode(proto::Goodbye{reason, static_cast<std::uint16_t>(proto::CloseCode::left)}));
    transport_->disconnect(0);
    transport_->flush();
    close(reason, why);
}

void Link::flush() {
    if (transport_) transport_->flush();
}

bool Link::poll(std::uint64_t now_us, std::vector<net::Event>& events) {
    now_us_ = now_us;
    if (reconnecting()) {
        const bool rejoin = state_ == LinkState::rejoin_due || state_ == LinkState::rejoining;
        const double window_s = rejoin ? config_.join_window_s : config_.reconnect_window_s;
        if (now_us_ - dropped_at_us_ > to_us(window_s)) {
            give_up(rejoin, window_s);
        } else if (connection_due() && now_us_ >= next_attempt_us_) {
            open_due_connection();
        }
    }
    if (!transport_) return false;
    events.clear();
    transport_->service(now_us / 1000, events);
    return true;
}

void Link::give_up(bool rejoin, double window_s) {
    // An attempt still under way must not be admitted after we gave up.
    if (transport_) {
        transport_->disconnect(0);
        transport_->flush();
    }
    const std::string within =
        std::string("could not ") + (rejoin ? "join" : "reconnect") + " within " + std::to_string(window_s) + " s";
    if (cap_refusals_ > 0) {
        return close(std::string(kCapRefusal) + "; " + within, proto::CloseCode::refused_pre_hello_cap);
    }
    close("disconnected: " + within, proto::CloseCode::local_connection_lost);
}

std::uint64_t Link::retry_delay_us() {
    const std::uint64_t retry = to_us(config_.reconnect_retry_s);
    if (cap_refusals_ == 0) return retry;
    const std::uint64_t base = retry << std::clamp(cap_refusals_ - 1, 0, kMaxBackoffDoublings);
    return std::uniform_int_distribution<std::uint64_t>(base / 2, base + base / 2)(jitter_);
}

void Link::open_due_connection() {
    // The old connection is dead: keep its figures, open a new one.
    past_totals_ = totals();
    owned_.reset();
    transport_ = nullptr;
    owned_ = connector_();
    transport_ = owned_.get();
    up_ = false;
    if (transport_) state_ = state_ == LinkState::rejoin_due ? LinkState::rejoining : LinkState::reconnecting;
    next_attempt_us_ = now_us_ + to_us(config_.reconnect_retry_s);
}

void Link::on_connection_event(const net::Event& e) {
    if (state_ == LinkState::closed) return;
    if (e.type == net::Event::Type::connected) {
        up_ = true;
        send_hello();
    }
    if (e.type == net::Event::Type::disconnected) on_disconnected(e.close_code);
}

void Link::send_hello() {
    proto::Hello h;
    h.name = config_.name;
    h.connect_token = config_.connect_token;
    h.observe = config_.observe;
    if (state_ == LinkState::reconnecting || state_ == LinkState::reconnect_due) {
        h.reconnect_token = reconnect_token_;
    } else {
        // A join (again): from here on like the first attempt. Once the Hello
        // is out the server may admit us, so a drop now is not retried (a
        // second Hello could take a second slot, or find its connect token
        // spent).
        state_ = LinkState::waiting_welcome;
        hello_sent_us_ = now_us_;
    }
    transport_->send(0, net::Channel::reliable, proto::encode(h));
}

void Link::on_disconnected(std::uint16_t code) {
    // The cap answers a connection request: only an attempt that never came up.
    const bool cap_refused = code == net::kPreHelloRefusal && !up_;
    cap_refusals_ = cap_refused ? cap_refusals_ + 1 : 0;
    up_ = false;
    if (cap_refused) spdlog::info("{}: {}", config_.name, kCapRefusal);
    if (reconnecting()) {
        if (goodbye_) return close_on_drop();  // the server said goodbye to the new connection
        state_ = state_ == LinkState::rejoining || state_ == LinkState::rejoin_due ? LinkState::rejoin_due
                                                                                  : LinkState::reconnect_due;
        if (cap_refused) next_attempt_us_ = std::max(next_attempt_us_, now_us_ + retry_delay_us());
    } else if (may_reconnect()) {
        spdlog::info("{}: connection lost; reconnecting to slot {}", config_.name, slot_);
        state_ = LinkState::reconnect_due;
        dropped_at_us_ = now_us_;
        next_attempt_us_ = now_us_;
    } else if (may_rejoin()) {
        spdlog::info("{}: {}; joining again", config_.name, goodbye_ ? server_said(*goodbye_) : "could not connect");
        goodbye_.reset();
        close_reason_.clear();
        state_ = LinkState::rejoin_due;
        dropped_at_us_ = now_us_;
        next_attempt_us_ = now_us_ + retry_delay_us();
    } else {
        close_on_drop();
    }
}

void Link::close_on_drop() {
    if (goodbye_) return close(server_said(*goodbye_), static_cast<proto::CloseCode>(goodbye_->code));
    if (cap_refusals_ > 0) return close(kCapRefusal, proto::CloseCode::refused_pre_hello_cap);
    close("disconnected", proto::CloseCode::local_connection_lost);
}

bool Link::may_reconnect() const {
    // Not after the server's Goodbye: it meant it.
    return connector_ && (state_ == LinkState::in_lobby || state_ == LinkState::racing) &&
           reconnect_token_.size() == proto::kTokenBytes && config_.reconnect_window_s > 0 && !goodbye_;
}

bool Link::may_rejoin() const {
    // Only when no Hello reached the server: the connection never came up,
    // or the server's Goodbye said it never got the Hello (lost on a bad
    // link): it admitted nothing, so joining again is safe.
    const bool no_hello = goodbye_ && goodbye_->code == static_cast<std::uint16_t>(proto::CloseCode::no_hello);
    const bool nothing_admitted =
        (state_ == LinkState::connecting && !goodbye_) || (state_ == LinkState::waiting_welcome && no_hello);
    return connector_ && config_.join_window_s > 0 && nothing_admitted;
}

void Link::check_welcome_timeout() {
    if (state_ == LinkState::waiting_welcome && config_.welcome_timeout_s > 0 &&
        now_us_ - hello_sent_us_ > to_us(config_.welcome_timeout_s)) {
        leave("no welcome within " + std::to_string(config_.welcome_timeout_s) + " s",
              proto::CloseCode::local_no_welcome);
    }
}

bool Link::on_welcome(const proto::Welcome& w) {
    const bool back = reconnecting();
    if (back && w.slot != slot_) spdlog::warn("{}: reconnected to slot {}, not {}", config_.name, w.slot, slot_);
    slot_ = w.slot;
    reconnect_token_ = w.reconnect_token;
    state_ = LinkState::in_lobby;
    return back;
}

void Link::on_refuse(const proto::Refuse& r) {
    close("refused: " + r.reason, static_cast<proto::CloseCode>(r.code));
}

void Link::on_goodbye(const proto::Goodbye& g) {
    if (state_ == LinkState::closed) return;
    goodbye_ = g;
    close_reason_ = server_said(g);  // the reason to close with, shown already
}

void Link::start_racing() {
    if (state_ == LinkState::in_lobby) state_ = LinkState::racing;
}

}  // namespace jetrace::client
