#include "http_server.hpp"

#include "static_files.hpp"
#include "ws_session.hpp"

#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <spdlog/spdlog.h>

#include <memory>

namespace jetrace::view {

namespace beast = boost::beast;
namespace http = boost::beast::http;
using tcp = boost::asio::ip::tcp;

namespace {

constexpr std::uint32_t kMaxRequestHeadBytes = 8 * 1024;
constexpr std::uint64_t kMaxRequestBodyBytes = 1024;

class HttpSession : public std::enable_shared_from_this<HttpSession> {
public:
    HttpSession(tcp::socket&& socket, ViewContext& ctx) : stream_(std::move(socket)), ctx_(ctx) {}
    void run() { read_next(); }

private:
    void read_next() {
        parser_.emplace();
        parser_->header_limit(kMaxRequestHeadBytes);
        parser_->body_limit(kMaxRequestBodyBytes);
        stream_.expires_after(std::chrono::seconds(30));
        http::async_read(stream_, buffer_, *parser_, beast::bind_front_handler(&HttpSession::on_read, shared_from_this()));
    }

    void on_read(beast::error_code ec, std::size_t) {
        if (ec == http::error::end_of_stream) return close();
        if (ec) {
            if (ec != beast::error::timeout) spdlog::debug("http: dropping a connection: {}", ec.message());
            return;
        }
        http::request<http::string_body> req = parser_->release();
        const bool full = ctx_.open_pages >= ctx_.settings.max_pages;
        if (beast::websocket::is_upgrade(req) && req.target() == "/ws" && full) {
            spdlog::warn("http: refusing a page: {} pages are open (--max-pages)", ctx_.open_pages);
        }
        if (beast::websocket::is_upgrade(req) && req.target() == "/ws" && !full) {
            stream_.expires_never();
            std::make_shared<WsSession>(stream_.release_socket(), ctx_)->run(std::move(req));
            return;
        }
        respond(req);
    }

    void respond(const http::request<http::string_body>& req) {
        auto res = std::make_shared<http::response<http::string_body>>(answer(req));
        res->version(req.version());
        res->keep_alive(req.keep_alive());
        res->set(http::field::server, "jetrace-view");
        res->set(http::field::cache_control, "no-store");
        res->prepare_payload();
        if (req.method() == http::verb::head) res->body().clear();
        http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code ec, std::size_t) {
            if (ec) return;
            if (!res->keep_alive()) return self->close();
            self->read_next();
        });
    }

    http::response<http::string_body> answer(const http::request<http::string_body>& req) const {
        if (req.method() != http::verb::get && req.method() != http::verb::head) {
            return plain(http::status::method_not_allowed, "only GET and HEAD\n");
        }
        const std::string_view target(req.target().data(), req.target().size());
        if (target == "/ws") {
            return beast::websocket::is_upgrade(req) ? plain(http::status::service_unavailable, "too many pages are open\n")
                                                     : plain(http::status::bad_request, "a WebSocket upgrade is expected here\n");
        }
        if (target == "/track.bin") return body(ctx_.track_bin, "application/octet-stream");
        const auto file = resolve_static(target, ctx_.settings.web_dir, ctx_.settings.node_modules_dir);
        if (!file) return plain(http::status::not_found, "not found\n");
        const auto text = read_whole_file(file->path);
        if (!text) {
            spdlog::error("http: cannot read {}", file->path);
            return plain(http::status::internal_server_error, "cannot read the file\n");
        }
        return body(*text, file->content_type);
    }

    static http::response<http::string_body> plain(http::status status, std::string text) {
        http::response<http::string_body> r{status, 11};
        r.set(http::field::content_type, "text/plain; charset=utf-8");
        r.body() = std::move(text);
        return r;
    }

    static http::response<http::string_body> body(std::string bytes, const std::string& type) {
        http::response<http::string_body> r{http::status::ok, 11};
        r.set(http::field::content_type, type);
        r.body() = std::move(bytes);
        return r;
    }

    void close() {
        beast::error_code ec;
        stream_.socket().shutdown(tcp::socket::shutdown_send, ec);
    }

    beast::tcp_stream stream_;
    beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
    ViewContext& ctx_;
};

}  // namespace

bool HttpServer::listen(const std::string& host, std::uint16_t port, std::string& error) {
    beast::error_code ec;
    const tcp::endpoint ep(boost::asio::ip::make_address(host, ec), port);
    if (!ec) acceptor_.open(ep.protocol(), ec);
    if (!ec) acceptor_.set_option(boost::asio::socket_base::reuse_address(true), ec);
    if (!ec) acceptor_.bind(ep, ec);
    if (!ec) acceptor_.listen(boost::asio::socket_base::max_listen_connections, ec);
    if (ec) error = "cannot listen on " + host + ":" + std::to_string(port) + ": " + ec.message();
    return !ec;
}

void HttpServer::accept_next() {
    acceptor_.async_accept([this](beast::error_code ec, tcp::socket socket) {
        if (ec) {
            spdlog::warn("http: accept failed: {}", ec.message());
        } else {
            std::make_shared<HttpSession>(std::move(socket), ctx_)->run();
        }
        if (acceptor_.is_open()) accept_next();
    });
}

}  // namespace jetrace::view
