// A live race seen through a real RaceClient over ENet. Drive mode: the
// client predicts and reconciles exactly as jetrace-bot's do, its own car
// driven by the keys a page sends. Watch mode: the client is an observer
// (no car) and the page is shown the race interpolated between the
// server's snapshots. The caller owns time: update() runs what is due by
// now. live_json.cpp turns it into page messages.
#pragma once

#include "live_race.hpp"

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace jetrace::view {

struct LiveOptions {
    /// The server (ADDR, UDP port).
    std::string host;
    std::uint16_t port = 0;
    /// The track file when the server's track is not built in ("": built-in tracks).
    std::string track_spec;
    /// The client's settings; name is the driver's name.
    client::ClientConfig client;
    /// Drive a car with the page's keys (else watch).
    bool drive = true;
};

class LiveSession {
public:
    /// Loads the known tracks (the --track file, or the built-in ones);
    /// false with a reason.
    bool load_tracks(const LiveOptions& o, std::string& error);
    /// Opens the connection; false with a reason.
    bool open(std::string& error);
    /// Blocks until the server welcomed the client and the client has the
    /// server's track (downloaded if it knew none with its identity); false
    /// with the reason if it refused, closed, or no Welcome came in the
    /// client's windows.
    bool wait_welcome(std::string& error);
    /// Handles the network and runs the ticks due by now.
    void update();

    /// Says goodbye to the server (its car is freed at once).
    void leave(const std::string& reason) { race_->client().leave(reason); }

    /// Keys from page `page` (the newest keys from any page count).
    void set_keys(std::uint64_t page, const KeysMessage& k);
    /// Page `page` closed: its keys are released.
    void release_keys(std::uint64_t page);

    bool driving() const { return options_.drive; }
    /// The race the pages are shown (after open()).
    const LiveRace& race() const { return *race_; }
    const client::RaceClient& client() const { return race_->client(); }
    /// The page's view of time: µs since open().
    std::uint64_t now_us() const;

private:
    LiveOptions options_;
    std::vector<std::unique_ptr<Scene>> scenes_;
    std::unique_ptr<LiveRace> race_;
    std::uint64_t keys_page_ = 0;
    std::chrono::steady_clock::time_point start_;
    bool closed_logged_ = false;
};

}  // namespace jetrace::view
