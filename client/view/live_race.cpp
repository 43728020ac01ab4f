#include "live_race.hpp"

namespace jetrace::view {

Input input_of(const KeysMessage& k) {
    const int steer = (k.right ? Input::kMaxSteer : 0) - (k.left ? Input::kMaxSteer : 0);
    return Input::clamped(k.up ? Input::kMaxThrottle : 0, steer, k.brake ? 1 : 0);
}

LiveRace::LiveRace(const client::ClientConfig& config, bool drive, client::KnownScenes scenes,
                   client::Connector connect)
    : drive_(drive), name_(config.name) {
    client::ClientConfig c = config;
    c.observe = !drive;
    client_ = std::make_unique<client::RaceClient>(c, std::move(scenes), std::move(connect));
}

void LiveRace::update(std::uint64_t now_us) {
    const Input in = input_;
    client_->update(now_us, [in](const Scene&, const WorldState&, int) { return in; });
    follow_timing();
}

void LiveRace::follow_timing() {
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

}  // namespace jetrace::view
