#include "jetrace/web/web_transport.hpp"

#include "game_socket.hpp"
#include "http_session.hpp"

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <spdlog/spdlog.h>

#include <thread>

namespace jetrace::web {

namespace {

using tcp = boost::asio::ip::tcp;
using detail::WebState;

class WebTransport final : public net::Transport {
public:
    explicit WebTransport(std::unique_ptr<WebState> state) : state_(std::move(state)), acceptor_(state_->io) {}

    // The I/O thread stops first; the sockets go with the state, the
    // handlers still queued with its io_context last.
    ~WebTransport() override {
        state_->io.stop();
        if (thread_.joinable()) thread_.join();
        boost::system::error_code ignored;
        acceptor_.close(ignored);
        state_->sockets.clear();
    }
    WebTransport(const WebTransport&) = delete;
    WebTransport& operator=(const WebTransport&) = delete;

    bool listen(std::uint16_t& port, std::string& error) {
        boost::system::error_code ec;
        const auto address = boost::asio::ip::make_address(state_->config.bind, ec);
        const tcp::endpoint ep(address, state_->config.port);
        if (!ec) acceptor_.open(ep.protocol(), ec);
        if (!ec) acceptor_.set_option(boost::asio::socket_base::reuse_address(true), ec);
        if (!ec) acceptor_.bind(ep, ec);
        if (!ec) acceptor_.listen(boost::asio::socket_base::max_listen_connections, ec);
        if (ec) {
            error = "cannot listen on " + state_->config.bind + ":" + std::to_string(state_->config.port) + " (--web): " +
                    ec.message();
            return false;
        }
        port = acceptor_.local_endpoint().port();
        accept_next();
        thread_ = std::thread([s = state_.get()] { s->io.run(); });
        return true;
    }

    void service(std::uint64_t, std::vector<net::Event>& events) override {
        std::lock_guard lock(state_->mutex);
        for (net::Event& e : state_->events) events.push_back(std::move(e));
        state_->events.clear();
    }

    bool send(net::PeerId peer, net::Channel channel, std::span<const std::uint8_t> data) override {
        std::shared_ptr<detail::GameSocket> s;
        {
            std::lock_guard lock(state_->mutex);
            const auto it = state_->sockets.find(peer);
            if (it == state_->sockets.end() || data.empty() || data.size() > state_->config.max_queued_bytes) return false;
            s = it->second;
            state_->totals.bytes_sent += data.size() + 1;
            ++state_->totals.packets_sent;
        }
        return s->queue(channel, data);
    }

    void disconnect(net::PeerId peer) override {
        std::lock_guard lock(state_->mutex);
        if (const auto it = state_->sockets.find(peer); it != state_->sockets.end()) it->second->close_after_writes(1000);
    }

    void admit(net::PeerId peer) override { state_->admit(peer); }
    void flush() override {}
    net::PeerStats peer_stats(net::PeerId) const override { return {}; }

    net::Totals totals() const override {
        std::lock_guard lock(state_->mutex);
        return state_->totals;
    }
    std::uint16_t local_port() const override { return acceptor_.local_endpoint().port(); }

    WebStats stats() const {
        std::lock_guard lock(state_->mutex);
        WebStats s = state_->stats;
        s.open_sockets = state_->sockets.size();
        return s;
    }

private:
    void accept_next() {
        acceptor_.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
            if (ec) {
                if (ec != boost::asio::error::operation_aborted) spdlog::warn("web: accept failed: {}", ec.message());
            } else {
                socket.set_option(tcp::no_delay(true), ec);
                detail::serve_http(std::move(socket), *state_);
            }
            if (acceptor_.is_open()) accept_next();
        });
    }

    std::unique_ptr<WebState> state_;
    tcp::acceptor acceptor_;
    std::thread thread_;
};

}  // namespace

std::string validate(const WebConfig& c) {
    if (c.max_sockets < 1 || c.max_sockets > 100000) return "web: max_sockets must be 1..100000";
    if (c.max_frame_bytes < 64 || c.max_frame_bytes > 1024 * 1024) return "web: max_frame_bytes must be 64..1048576";
    if (c.max_queued_bytes < 64 * 1024 || c.max_queued_bytes > 64 * 1024 * 1024) {
        return "web: max_queued_bytes must be 65536..67108864";
    }
    if (c.timeout_ms < 500 || c.timeout_ms > 600000) return "web: timeout_ms must be 500..600000";
    if (c.cert_file.empty() != c.key_file.empty()) return "--web-cert and --web-key go together";
    for (const std::string& o : c.origins) {
        if (o.rfind("http://", 0) != 0 && o.rfind("https://", 0) != 0) {
            return "--web-origin " + o + ": an origin is http://HOST[:PORT] or https://HOST[:PORT]";
        }
    }
    return {};
}

namespace {

/// The TLS context of --web-cert and --web-key; null and `error` if they
/// do not load or do not match.
std::unique_ptr<boost::asio::ssl::context> tls_context(const WebConfig& c, std::string& error) {
    namespace ssl = boost::asio::ssl;
    auto ctx = std::make_unique<ssl::context>(ssl::context::tls_server);
    ctx->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                     ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1);
    boost::system::error_code ec;
    ctx->use_certificate_chain_file(c.cert_file, ec);
    if (ec) {
        error = "--web-cert " + c.cert_file + ": " + ec.message();
        return nullptr;
    }
    ctx->use_private_key_file(c.key_file, ssl::context::pem, ec);
    if (ec) {
        error = "--web-key " + c.key_file + ": " + ec.message() + " (or it is not the key of --web-cert)";
        return nullptr;
    }
    return ctx;
}

}  // namespace

std::unique_ptr<net::Transport> listen_web(const WebConfig& config, WebSite site, std::uint16_t& port,
                                           std::string& error) {
    if (error = validate(config); !error.empty()) return nullptr;
    auto state = std::make_unique<WebState>(config, std::move(site));
    if (!config.cert_file.empty()) {
        state->tls = tls_context(config, error);
        if (!state->tls) return nullptr;
    }
    auto t = std::make_unique<WebTransport>(std::move(state));
    if (!t->listen(port, error)) return nullptr;
    return t;
}

WebStats web_stats(const net::Transport& transport) {
    const auto* t = dynamic_cast<const WebTransport*>(&transport);
    return t != nullptr ? t->stats() : WebStats{};
}

}  // namespace jetrace::web
