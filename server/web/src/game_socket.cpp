#include "game_socket.hpp"

#include "jetrace/net/ws_frame.hpp"

#include <boost/asio/post.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <deque>

namespace jetrace::web::detail {

namespace beast = boost::beast;
namespace websocket = boost::beast::websocket;

namespace {

template <class Stream>
class GameSocketOn final : public GameSocket {
public:
    GameSocketOn(Stream&& stream, WebState& state, std::string address)
        : GameSocket(state, std::move(address)), ws_(std::move(stream)) {}

    void run(Request req);
    bool queue(net::Channel channel, std::span<const std::uint8_t> data) override;
    void close_after_writes(std::uint16_t code) override;

private:
    std::shared_ptr<GameSocketOn> self() { return std::static_pointer_cast<GameSocketOn>(shared_from_this()); }
    void on_accept(beast::error_code ec);
    void read_next();
    void on_read(beast::error_code ec, std::size_t bytes);
    void push(std::string frame);
    void write_front();
    void on_write(beast::error_code ec, std::size_t bytes);
    void close(std::uint16_t code);
    void finish(std::uint16_t code);
    /// Tells the server (once) that the socket is closed, with `code`.
    void report(std::uint16_t code);

    websocket::stream<Stream> ws_;
    beast::flat_buffer in_;
    std::deque<std::string> out_;
    std::atomic<std::size_t> queued_bytes_{0};
    std::atomic<bool> overflowed_{false};
    bool writing_ = false;
    bool closing_ = false;
    bool finished_ = false;
    bool open_ = false;
    bool reported_ = false;
    std::uint16_t close_code_ = 0;
};

template <class Stream>
void GameSocketOn<Stream>::run(Request req) {
    websocket::stream_base::timeout t{};
    t.handshake_timeout = std::chrono::seconds(10);
    t.idle_timeout = std::chrono::milliseconds(state_->config.timeout_ms);
    t.keep_alive_pings = true;
    ws_.set_option(t);
    ws_.read_message_max(state_->config.max_frame_bytes + 1);
    ws_.binary(true);
    ws_.async_accept(req, beast::bind_front_handler(&GameSocketOn::on_accept, self()));
}

template <class Stream>
void GameSocketOn<Stream>::on_accept(beast::error_code ec) {
    if (ec) {
        spdlog::debug("web: WebSocket handshake with {} failed: {}", address_, ec.message());
        return finish(0);
    }
    open_ = true;
    state_->opened(shared_from_this());
    read_next();
}

template <class Stream>
void GameSocketOn<Stream>::read_next() {
    ws_.async_read(in_, beast::bind_front_handler(&GameSocketOn::on_read, self()));
}

template <class Stream>
void GameSocketOn<Stream>::on_read(beast::error_code ec, std::size_t) {
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

template <class Stream>
bool GameSocketOn<Stream>::queue(net::Channel channel, std::span<const std::uint8_t> data) {
    const std::size_t size = data.size() + 1;
    if (overflowed_) return false;
    if (queued_bytes_.fetch_add(size) + size > state_->config.max_queued_bytes) {
        overflowed_ = true;
        close_after_writes(kSendQueueFull);
        return false;
    }
    std::string frame = net::ws_frame(channel, data);
    boost::asio::post(state_->io, [self = self(), f = std::move(frame)]() mutable { self->push(std::move(f)); });
    return true;
}

template <class Stream>
void GameSocketOn<Stream>::close_after_writes(std::uint16_t code) {
    boost::asio::post(state_->io, [self = self(), code] {
        if (code == kSendQueueFull) {
            // A socket that cannot keep up loses what waits: the close goes now.
            self->out_.resize(self->writing_ ? 1 : 0);
        }
        self->close_code_ = code;
        if (!self->writing_) self->close(code);
    });
}

template <class Stream>
void GameSocketOn<Stream>::push(std::string frame) {
    if (closing_ || finished_) return;
    out_.push_back(std::move(frame));
    if (!writing_) write_front();
}

template <class Stream>
void GameSocketOn<Stream>::write_front() {
    writing_ = true;
    ws_.async_write(boost::asio::buffer(out_.front()), beast::bind_front_handler(&GameSocketOn::on_write, self()));
}

template <class Stream>
void GameSocketOn<Stream>::on_write(beast::error_code ec, std::size_t) {
    writing_ = false;
    if (ec) return finish(0);
    queued_bytes_.fetch_sub(out_.front().size());
    out_.pop_front();
    if (close_code_ != 0 && !closing_) return close(close_code_);
    if (!out_.empty() && !closing_) write_front();
}

template <class Stream>
void GameSocketOn<Stream>::close(std::uint16_t code) {
    if (closing_ || finished_) return;
    closing_ = true;
    close_code_ = code;
    // The server hears of it now: a peer that reads nothing (a full send
    // queue) would hold the close handshake until its timeout.
    report(code);
    // The frame being written stays until its write completes.
    out_.resize(writing_ ? 1 : 0);
    ws_.async_close(websocket::close_reason(code), [self = self(), code](beast::error_code) {
        self->finish(code);
    });
}

template <class Stream>
void GameSocketOn<Stream>::report(std::uint16_t code) {
    if (reported_) return;
    reported_ = true;
    if (open_) state_->closed(*this, code);
    else state_->abandoned(address_);
}

template <class Stream>
void GameSocketOn<Stream>::finish(std::uint16_t code) {
    if (finished_) return;
    finished_ = true;
    report(code != 0 ? code : close_code_);
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
}

}  // namespace

void open_game_socket(PlainStream&& stream, WebState& state, std::string address, Request req) {
    std::make_shared<GameSocketOn<PlainStream>>(std::move(stream), state, std::move(address))->run(std::move(req));
}

void open_game_socket(TlsStream&& stream, WebState& state, std::string address, Request req) {
    std::make_shared<GameSocketOn<TlsStream>>(std::move(stream), state, std::move(address))->run(std::move(req));
}

}  // namespace jetrace::web::detail
