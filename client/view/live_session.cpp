#include "live_session.hpp"

#include <spdlog/spdlog.h>

#include <thread>

namespace jetrace::view {

using client::ClientState;

bool LiveSession::load_tracks(const LiveOptions& o, std::string& error) {
    options_ = o;
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
    race_ = std::make_unique<LiveRace>(o.client, o.drive, known, [host, port] {
        std::string e;
        auto t = net::connect_enet(host, port, 5000, e);
        if (!t) spdlog::error("cannot connect to {}:{}: {}", host, port, e);
        return t;
    });
    if (client().state() == ClientState::closed) {
        error = "cannot open a connection to " + host + ":" + std::to_string(port);
        return false;
    }
    return true;
}

bool LiveSession::wait_welcome(std::string& error) {
    // Welcomed, the client may still be fetching the server's track: the
    // page is served the track's mesh, so that waits for it too.
    while (client().state() == ClientState::connecting || client().state() == ClientState::waiting_welcome ||
           client().state() == ClientState::reconnecting ||
           (client().state() != ClientState::closed && client().downloading_track())) {
        update();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (client().state() == ClientState::closed) {
        error = "cannot join the race at " + options_.host + ":" + std::to_string(options_.port) + ": " +
                client().close_reason() + " (code " + std::to_string(client().close_code()) + ")";
        return false;
    }
    if (client().observer()) {
        spdlog::info("watching {}:{} as observer {}, track {}", options_.host, options_.port, options_.client.name,
                     client().scene().track.name);
    } else {
        spdlog::info("joined {}:{} as {} (slot {}), track {}", options_.host, options_.port, options_.client.name,
                     client().slot(), client().scene().track.name);
    }
    return true;
}

std::uint64_t LiveSession::now_us() const {
    const auto d = std::chrono::steady_clock::now() - start_;
    return static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(d).count());
}

void LiveSession::update() {
    race_->update(now_us());
    if (client().state() == ClientState::closed && !closed_logged_) {
        closed_logged_ = true;
        spdlog::info("the race connection closed: {} (code {})", client().close_reason(), client().close_code());
    }
}

void LiveSession::set_keys(std::uint64_t page, const KeysMessage& k) {
    race_->set_keys(k);
    keys_page_ = page;
}

void LiveSession::release_keys(std::uint64_t page) {
    if (page != keys_page_) return;
    race_->set_keys(KeysMessage{});
    keys_page_ = 0;
}

}  // namespace jetrace::view
