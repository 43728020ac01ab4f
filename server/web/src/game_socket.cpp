#include "game_socket.hpp"

#include "jetrace/net/ws_frame.hpp"

#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

namespace jetrace::web::detail {

namespace beast = boost::beast;
namespace websocket = boost::beast::websocket;

GameSocket::GameSocket(boost::asio::ip::tcp::socket&& socket, WebState& state, std::string address)
    : ws_(std::move(socket)), state_(&state), address_(std::move(address)) {}

void GameSocket::run(beast::http::request<beast::http::string_body> req) {
    websocket::stream_base::timeout t{};
    t.handshake_timeout = std::chrono::seconds(10);
    t.idle_timeout = std::chrono::milliseconds(state_->config.timeout_ms);
    t.keep_alive_pings = true;
    ws_.set_option(t);
    ws_.read_message_max(state_->config.max_frame_bytes + 1);
    ws_.binary(true);
    ws_.async_accept(req, beast::bind_front_handler(&GameSocket::on_accept, shared_from_this()));
}

void GameSocket::on_accept(beast::error_code ec) {
    if (ec) {
        spdlog::debug("web: WebSocket handshake with {} failed: {}", address_, ec.message());
        return finish(0);
    }
    open_ = true;
    state_->opened(shared_from_this());
    read_next();
}

void GameSocket::read_next() {
    ws_.async_read(in_, beast::bind_front_handler(&GameSocket::on_read, shared_from_this()));
}

void GameSocket::on_read(beast::error_code ec, std::size_t) {
    if (ec == websocket::error::message_too_big) return close(kMalformedFrame);
    if (ec) return finish(ec == websocket::error::closed ? ws_.reason().code : 0);
    const auto bytes = in_.data();
    const std::span<const std::uint8_t> frame(static_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    net::Channel channel{};
    std::span<const std::uint8_t> message;
    if (!ws_.got_binary() || !net::read_ws_frame(frame, channel, message)) {
        in_.consume(in_.size());
        return close(kMalformedFrame);
    }
    state_->received(peer_, channel, std::vector<std::uint8_t>(message.begin(), message.end()));
    in_.consume(in_.size());
    if (!closing_) read_next();
}

bool GameSocket::queue(net::Channel channel, std::span<const std::uint8_t> data) {
    const std::size_t size = data.size() + 1;
    if (overflowed_) return false;
    if (queued_bytes_.fetch_add(size) + size > state_->config.max_queued_bytes) {
        overflowed_ = true;
        close_after_writes(kSendQueueFull);
        return false;
    }
    std::string frame = net::ws_frame(channel, data);
    boost::asio::post(state_->io, [self = shared_from_this(), f = std::move(frame)]() mutable { self->push(std::move(f)); });
    return true;
}

void GameSocket::close_after_writes(std::uint16_t code) {
    boost::asio::post(state_->io, [self = shared_from_this(), code] {
        if (code == kSendQueueFull) {
            // A socket that cannot keep up loses what waits: the close goes now.
            self->out_.resize(self->writing_ ? 1 : 0);
        }
        self->close_code_ = code;
        if (!self->writing_) self->close(code);
    });
}

void GameSocket::push(std::string frame) {
    if (closing_ || finished_) return;
    out_.push_back(std::move(frame));
    if (!writing_) write_front();
}

void GameSocket::write_front() {
    writing_ = true;
    ws_.async_write(boost::asio::buffer(out_.front()), beast::bind_front_handler(&GameSocket::on_write, shared_from_this()));
}

void GameSocket::on_write(beast::error_code ec, std::size_t) {
    writing_ = false;
    if (ec) return finish(0);
    queued_bytes_.fetch_sub(out_.front().size());
    out_.pop_front();
    if (close_code_ != 0 && !closing_) return close(close_code_);
    if (!out_.empty() && !closing_) write_front();
}

void GameSocket::close(std::uint16_t code) {
    if (closing_ || finished_) return;
    closing_ = true;
    close_code_ = code;
    // The server hears of it now: a peer that reads nothing (a full send
    // queue) would hold the close handshake until its timeout.
    report(code);
    // The frame being written stays until its write completes.
    out_.resize(writing_ ? 1 : 0);
    ws_.async_close(websocket::close_reason(code), [self = shared_from_this(), code](beast::error_code) {
        self->finish(code);
    });
}

void GameSocket::report(std::uint16_t code) {
    if (reported_) return;
    reported_ = true;
    if (open_) state_->closed(*this, code);
    else state_->abandoned(address_);
}

void GameSocket::finish(std::uint16_t code) {
    if (finished_) return;
    finished_ = true;
    report(code != 0 ? code : close_code_);
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
}

}  // namespace jetrace::web::detail
