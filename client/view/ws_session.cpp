#include "ws_session.hpp"

#include "drive_messages.hpp"
#include "live_json.hpp"
#include "page_messages.hpp"
#include "world_json.hpp"

#include <spdlog/spdlog.h>

namespace jetrace::view {

namespace beast = boost::beast;
namespace websocket = boost::beast::websocket;
using Clock = std::chrono::steady_clock;

WsSession::WsSession(boost::asio::ip::tcp::socket&& socket, ViewContext& ctx)
    : ws_(std::move(socket)),
      timer_(ws_.get_executor()),
      ctx_(ctx),
      id_(ctx.next_page++) {
    if (ctx.main) {
        playback_.emplace(*ctx.main, ctx.ghost_players());
        playback_->set_speed(ctx.settings.speed);
    }
    ++ctx_.open_pages;
}

WsSession::~WsSession() { --ctx_.open_pages; }

void WsSession::run(beast::http::request<beast::http::string_body> req) {
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxPageMessageBytes);
    ws_.async_accept(req, beast::bind_front_handler(&WsSession::on_accept, shared_from_this()));
}

void WsSession::on_accept(beast::error_code ec) {
    if (ec) return spdlog::warn("page {}: WebSocket handshake failed: {}", id_, ec.message());
    spdlog::info("page {}: connected", id_);
    opened_ = last_advance_ = Clock::now();
    ws_.text(true);
    send(playback_ ? hello_json(*playback_) : live_hello_json(ctx_.live->race()), false);
    if (playback_) playback_->set_playing(!ctx_.settings.paused);
    send(frame(), true);
    read_next();
    arm_timer();
}

void WsSession::read_next() {
    ws_.async_read(in_, beast::bind_front_handler(&WsSession::on_read, shared_from_this()));
}

void WsSession::on_read(beast::error_code ec, std::size_t) {
    if (ec == websocket::error::closed) return finish("closed by the page");
    if (ec == websocket::error::message_too_big) {
        return close(websocket::close_code::too_big, "message longer than " + std::to_string(kMaxPageMessageBytes) + " bytes");
    }
    if (ec) return finish(ec.message());
    if (!ws_.got_text()) return close(websocket::close_code::bad_payload, "binary message");
    const std::string text = beast::buffers_to_string(in_.data());
    in_.consume(in_.size());
    apply(text);
    if (!closing_) read_next();
}

std::string WsSession::frame() const { return playback_ ? frame_json(*playback_) : live_frame_json(ctx_.live->race()); }

void WsSession::apply_live(const std::string& text) {
    if (!ctx_.live->driving()) return close(websocket::close_code::policy_error, "a watching page sends nothing");
    KeysMessage k;
    std::string error;
    if (!parse_keys_message(text, k, error)) return close(websocket::close_code::policy_error, error);
    ctx_.live->set_keys(id_, k);
}

void WsSession::apply(const std::string& text) {
    if (!playback_) return apply_live(text);
    PageMessage m;
    std::string error;
    const PageLimits limits{ctx_.main->first_tick(), ctx_.main->last_tick()};
    if (!parse_page_message(text, limits, m, error)) return close(websocket::close_code::policy_error, error);
    if (const auto* play = std::get_if<PlayMessage>(&m)) {
        playback_->set_playing(play->playing);
        last_advance_ = Clock::now();
    } else if (const auto* speed = std::get_if<SpeedMessage>(&m)) {
        playback_->set_speed(speed->speed);
    } else if (const auto* seek = std::get_if<SeekMessage>(&m)) {
        playback_->seek(seek->tick);
    }
    send(frame(), true);
}

void WsSession::arm_timer() {
    timer_.expires_after(std::chrono::microseconds(1'000'000 / ctx_.settings.frame_rate_hz));
    timer_.async_wait(beast::bind_front_handler(&WsSession::on_timer, shared_from_this()));
}

void WsSession::on_timer(beast::error_code ec) {
    if (ec || closing_) return;
    const Clock::time_point now = Clock::now();
    const double real_s = std::chrono::duration<double>(now - last_advance_).count();
    last_advance_ = now;
    if (!playback_) {
        send(frame(), true);  // live: the world moves on by itself
    } else {
        const bool was_playing = playback_->playing();
        if (playback_->advance(real_s) || was_playing != playback_->playing()) send(frame(), true);
    }
    arm_timer();
}

void WsSession::send(std::string message, bool is_frame) {
    if (closing_) return;
    if (is_frame && last_is_frame_ && out_.size() > 1) {
        out_.back() = std::move(message);  // the page has not read the last one yet: send only the newest
        return;
    }
    out_.push_back(std::move(message));
    last_is_frame_ = is_frame;
    if (out_.size() == 1) write_front();
}

void WsSession::write_front() {
    ws_.async_write(boost::asio::buffer(out_.front()), beast::bind_front_handler(&WsSession::on_write, shared_from_this()));
}

void WsSession::on_write(beast::error_code ec, std::size_t bytes) {
    if (ec) return finish("write failed: " + ec.message());
    bytes_sent_ += bytes;
    out_.pop_front();
    if (out_.empty()) last_is_frame_ = false;
    if (!out_.empty() && !closing_) write_front();
}

void WsSession::close(websocket::close_code code, const std::string& why) {
    spdlog::warn("page {}: malformed message ({}); closing its socket", id_, why);
    closing_ = true;
    timer_.cancel();
    ws_.async_close(code, [self = shared_from_this()](beast::error_code) { self->finish("closed after a malformed message"); });
}

void WsSession::finish(const std::string& why) {
    closing_ = true;
    if (finished_) return;
    finished_ = true;
    timer_.cancel();
    if (ctx_.live) ctx_.live->release_keys(id_);
    const double s = std::chrono::duration<double>(Clock::now() - opened_).count();
    spdlog::info("page {}: {}; {} bytes sent in {:.1f} s ({:.0f} B/s)", id_, why, bytes_sent_, s,
                 s > 0 ? static_cast<double>(bytes_sent_) / s : 0.0);
}

}  // namespace jetrace::view
