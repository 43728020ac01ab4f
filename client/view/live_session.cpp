#include "live_session.hpp"

#include <spdlog/spdlog.h>

#include <thread>

namespace jetrace::view {

using client::ClientState;

Input input_of(const KeysMessage& k) {
    const int steer = (k.right ? Input::kMaxSteer : 0) - (k.left ? Input::kMaxSteer : 0);
    return Input::clamped(k.up ? Input::kMaxThrottle : 0, steer, k.brake ? 1 : 0);
}

bool LiveSession::load_tracks(const LiveOptions& o, std::string& error) {
    options_ = o;
    options_.client.observe = !o.drive;
    scenes_.clear();
    return client::load_known_scenes(o.track_spec, scenes_, error);
}

bool LiveSession::open(std::string& error) {
    const LiveOptions& o = options_;
    client::KnownScenes known;
    for (const auto& sc : scenes_) known.push_back(sc.get());
    start_ = std::chrono::steady_clock::now();
    const std::string host = o.host;
    const std::uint16_t port = o.port;
    client_ = std::make_unique<client::RaceClient>(o.client, known, [host, port] {
        std::string e;
        auto t = net::connect_enet(host, port, 5000, e);
        if (!t) spdlog::error("cannot connect to {}:{}: {}", host, port, e);
        return t;
    });
    if (client_->state() == ClientState::closed) {
        error = "cannot open a connection to " + host + ":" + std::to_string(port);
        return false;
    }
    return true;
}

bool LiveSession::wait_welcome(std::string& error) {
    // Welcomed, the client may still be fetching the server's track: the
    // page is served the track's mesh, so that waits for it too.
    while (client_->state() == ClientState::connecting || client_->state() == ClientState::waiting_welcome ||
           client_->state() == ClientState::reconnecting ||
           (client_->state() != ClientState::closed && client_->downloading_track())) {
        update();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (client_->state() == ClientState::closed) {
        error = "cannot join the race at " + options_.host + ":" + std::to_string(options_.port) + ": " +
                client_->close_reason() + " (code " + std::to_string(client_->close_code()) + ")";
        return false;
    }
    if (client_->observer()) {
        spdlog::info("watching {}:{} as observer {}, track {}", options_.host, options_.port, options_.client.name,
                     client_->scene().track.name);
    } else {
        spdlog::info("joined {}:{} as {} (slot {}), track {}", options_.host, options_.port, options_.client.name,
                     client_->slot(), client_->scene().track.name);
    }
    return true;
}

std::uint64_t LiveSession::now_us() const {
    const auto d = std::chrono::steady_clock::now() - start_;
    return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(d).count());
}

void LiveSession::update() {
    const Input in = input_of(keys_);
    client_->update(now_us(), [in](const Scene&, const WorldState&, int) { return in; });
    follow_timing();
    if (client_->state() == ClientState::closed && !closed_logged_) {
        closed_logged_ = true;
        spdlog::info("the race connection closed: {} (code {})", client_->close_reason(), client_->close_code());
    }
}

void LiveSession::follow_timing() {
    const WorldState& a = client_->authoritative();
    if (a.cars.empty() || a.tick == timing_tick_) return;
    if (timing_tick_ == proto::kNoTick || client_->race_number() != timing_race_ || a.tick < timing_tick_) {
        timing_.start(a, static_cast<int>(client_->scene().track.checkpoints.size()));
        timing_race_ = client_->race_number();
    } else {
        timing_.after_step(a);
    }
    timing_tick_ = a.tick;
}

void LiveSession::set_keys(std::uint64_t page, const KeysMessage& k) {
    keys_ = k;
    keys_page_ = page;
}

void LiveSession::release_keys(std::uint64_t page) {
    if (page != keys_page_) return;
    keys_ = KeysMessage{};
    keys_page_ = 0;
}

}  // namespace jetrace::view
