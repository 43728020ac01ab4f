#include "http_session.hpp"

#include "game_socket.hpp"

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>
#include <type_traits>

namespace jetrace::web::detail {

namespace beast = boost::beast;
namespace http = boost::beast::http;
using tcp = boost::asio::ip::tcp;

namespace {

constexpr std::uint32_t kMaxRequestHeadBytes = 8 * 1024;
/// Room for a WebRTC offer (webrtc::kMaxOfferBytes, 16 KiB) and more, so
/// that an offer too large is answered 400 by the parser of offers.
constexpr std::uint64_t kMaxRequestBodyBytes = 32 * 1024;
constexpr std::string_view kPlayPath = "/play";
constexpr std::string_view kRtcPath = "/rtc";

using Response = http::response<http::string_body>;

Response plain(http::status status, std::string text) {
    Response r{status, 11};
    r.set(http::field::content_type, "text/plain; charset=utf-8");
    r.body() = std::move(text);
    return r;
}

// PlainStream (HTTP) or TlsStream (HTTPS: the TLS handshake first).
template <class Stream>
class HttpSession : public std::enable_shared_from_this<HttpSession<Stream>> {
public:
    HttpSession(tcp::socket&& socket, WebState& state) : stream_(make_stream(std::move(socket), state)), state_(&state) {
        beast::error_code ec;
        const auto ep = beast::get_lowest_layer(stream_).socket().remote_endpoint(ec);
        if (!ec) address_ = ep.address().to_string();
        const auto local = beast::get_lowest_layer(stream_).socket().local_endpoint(ec);
        if (!ec) local_ip_ = local.address().to_string();
    }
    void run() {
        if constexpr (std::is_same_v<Stream, TlsStream>) {
            beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(10));
            stream_.async_handshake(boost::asio::ssl::stream_base::server,
                                    [self = this->shared_from_this()](beast::error_code ec) {
                                        if (!ec) self->read_next();
                                    });
        } else {
            read_next();
        }
    }

private:
    static Stream make_stream(tcp::socket&& socket, WebState& state) {
        if constexpr (std::is_same_v<Stream, TlsStream>) return Stream(std::move(socket), *state.tls);
        else return Stream(std::move(socket));
    }

    void read_next() {
        parser_.emplace();
        parser_->header_limit(kMaxRequestHeadBytes);
        parser_->body_limit(kMaxRequestBodyBytes);
        beast::get_lowest_layer(stream_).expires_after(std::chrono::seconds(30));
        http::async_read(stream_, buffer_, *parser_,
                         beast::bind_front_handler(&HttpSession::on_read, this->shared_from_this()));
    }

    void on_read(beast::error_code ec, std::size_t) {
        if (ec == http::error::end_of_stream) return close();
        if (ec == http::error::body_limit) {
            http::request<http::string_body> req{http::verb::post, kRtcPath, 11};
            req.keep_alive(false);
            return respond(req, plain(http::status::bad_request, "request body too large\n"));
        }
        if (ec) return;
        http::request<http::string_body> req = parser_->release();
        const std::string_view target(req.target().data(), req.target().size());
        if (target == kRtcPath) return respond(req, signal(req));
        if (target != kPlayPath || !beast::websocket::is_upgrade(req)) return respond(req, answer(req));
        if (!allowed_origin(req)) {
            {
                std::lock_guard lock(state_->mutex);
                ++state_->stats.origin_refusals;
            }
            spdlog::info("web: refused a game socket from {}: Origin {} is not allowed (--web-origin)", address_,
                         std::string_view(req[http::field::origin].data(), req[http::field::origin].size()));
            return respond(req, plain(http::status::forbidden, "this origin may not open a game socket\n"));
        }
        const auto admission = state_->reserve(address_);
        if (admission != WebState::Admission::open) {
            Response r = plain(http::status::service_unavailable,
                               admission == WebState::Admission::full ? "too many game sockets are open\n"
                                                                      : "too many connections from your address are joining\n");
            r.set(http::field::retry_after, "1");
            return respond(req, std::move(r));
        }
        beast::get_lowest_layer(stream_).expires_never();
        open_game_socket(std::move(stream_), *state_, address_, std::move(req));
    }

    bool allowed_origin(const http::request<http::string_body>& req) const {
        const std::string_view origin(req[http::field::origin].data(), req[http::field::origin].size());
        const std::string_view host(req[http::field::host].data(), req[http::field::host].size());
        return origin_allowed(origin, host, state_->config.origins);
    }

    // POST /rtc: the WebRTC offer, answered by the signalling (server/rtc).
    Response signal(const http::request<http::string_body>& req) const {
        if (!state_->config.rtc_signal) return plain(http::status::not_found, "no WebRTC data channels here\n");
        if (req.method() != http::verb::post) return plain(http::status::method_not_allowed, "POST an SDP offer\n");
        if (!allowed_origin(req)) {
            spdlog::info("web: refused an offer from {}: its Origin is not allowed (--web-origin)", address_);
            return plain(http::status::forbidden, "this origin may not open a data channel\n");
        }
        const SignalReply reply = state_->config.rtc_signal(req.body(), address_, local_ip_);
        Response r{static_cast<http::status>(reply.status), 11};
        r.set(http::field::content_type, reply.content_type);
        if (reply.status == 503) r.set(http::field::retry_after, "1");
        r.body() = reply.body;
        return r;
    }

    Response answer(const http::request<http::string_body>& req) const {
        if (req.method() != http::verb::get && req.method() != http::verb::head) {
            return plain(http::status::method_not_allowed, "only GET and HEAD\n");
        }
        std::string_view target(req.target().data(), req.target().size());
        if (target == kPlayPath) return plain(http::status::bad_request, "a WebSocket upgrade is expected here\n");
        if (const auto q = target.find('?'); q != std::string_view::npos) target = target.substr(0, q);
        const auto it = state_->site.find(std::string(target));
        if (it == state_->site.end()) return plain(http::status::not_found, "not found\n");
        Response r{http::status::ok, 11};
        r.set(http::field::content_type, it->second.content_type);
        r.set(http::field::vary, "Accept-Encoding");
        const std::string_view accept(req[http::field::accept_encoding].data(), req[http::field::accept_encoding].size());
        if (!it->second.gzipped.empty() && accept.find("gzip") != std::string_view::npos) {
            r.set(http::field::content_encoding, "gzip");
            r.body() = it->second.gzipped;
        } else {
            r.body() = it->second.bytes;
        }
        return r;
    }

    void respond(const http::request<http::string_body>& req, Response res) {
        auto out = std::make_shared<Response>(std::move(res));
        out->version(req.version());
        out->keep_alive(req.keep_alive());
        out->set(http::field::server, "jetrace-server");
        out->set(http::field::cache_control, "no-store");
        out->prepare_payload();
        if (req.method() == http::verb::head) out->body().clear();
        http::async_write(stream_, *out, [self = this->shared_from_this(), out](beast::error_code ec, std::size_t) {
            if (ec) return;
            if (!out->keep_alive()) return self->close();
            self->read_next();
        });
    }

    void close() {
        if constexpr (std::is_same_v<Stream, TlsStream>) {
            stream_.async_shutdown([self = this->shared_from_this()](beast::error_code) {});
        } else {
            beast::error_code ec;
            stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
        }
    }

    Stream stream_;
    WebState* state_;
    std::string address_;
    std::string local_ip_;
    beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
};

}  // namespace

void serve_http(tcp::socket&& socket, WebState& state) {
    if (state.tls) std::make_shared<HttpSession<TlsStream>>(std::move(socket), state)->run();
    else std::make_shared<HttpSession<PlainStream>>(std::move(socket), state)->run();
}

bool origin_allowed(std::string_view origin, std::string_view host, const std::vector<std::string>& allowed) {
    if (origin.empty()) return true;
    if (!host.empty()) {
        for (std::string_view scheme : {"http://", "https://"}) {
            if (origin.size() == scheme.size() + host.size() && origin.substr(0, scheme.size()) == scheme &&
                origin.substr(scheme.size()) == host) {
                return true;
            }
        }
    }
    return std::find(allowed.begin(), allowed.end(), origin) != allowed.end();
}

}  // namespace jetrace::web::detail
