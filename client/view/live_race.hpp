// A live race as a page shows it: a RaceClient (its own car driven by the
// page's keys, or an observer), and the lap and gap timing of what its
// snapshots showed. No sockets and no clock: the caller owns both (the
// native LiveSession over ENet, the WebAssembly client over the page's
// WebSocket). live_json.cpp turns it into page messages.
#pragma once

#include "drive_messages.hpp"
#include "race_timing.hpp"

#include "jetrace/client/race_client.hpp"

#include <cstdint>
#include <memory>
#include <string>

namespace jetrace::view {

/// The input the keys ask for: full throttle on up, full steer left or
/// right (both: none), the brake.
Input input_of(const KeysMessage& k);

class LiveRace {
public:
    /// Drives a car (`drive`) or watches; connects through `connect` now.
    LiveRace(const client::ClientConfig& config, bool drive, client::KnownScenes scenes, client::Connector connect);

    /// Handles the network and runs the ticks due by `now_us`.
    void update(std::uint64_t now_us);
    /// The keys held now (driving): input_of(k) from now on.
    void set_keys(const KeysMessage& k) { input_ = input_of(k); }
    /// The input from now on (a gamepad's analog one).
    void set_input(const Input& in) { input_ = in; }
    /// The input the next ticks are driven with.
    const Input& input() const { return input_; }

    bool driving() const { return drive_; }
    /// The world the page is shown (cars, laps, gates, start tick): driving,
    /// the client's prediction of its own race; watching, every car at the
    /// render tick, between the two snapshots of RaceClient::render_span().
    WorldState world() const { return drive_ ? client_->predicted() : client_->render_world(); }
    const std::string& driver() const { return name_; }
    const client::RaceClient& client() const { return *client_; }
    client::RaceClient& client() { return *client_; }
    const RaceTiming& timing() const { return timing_; }

private:
    void follow_timing();

    bool drive_;
    std::string name_;
    std::unique_ptr<client::RaceClient> client_;
    Input input_{};
    RaceTiming timing_;
    std::uint32_t timing_race_ = 0;
    std::uint32_t timing_tick_ = proto::kNoTick;
};

}  // namespace jetrace::view
