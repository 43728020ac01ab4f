#include "replay_player.hpp"

#include "jetrace/replay/scanner.hpp"
#include "jetrace/replay/source.hpp"

#include <algorithm>
#include <utility>

namespace jetrace::view {

bool ReplayPlayer::load(const std::string& path, replay::SceneFor scenes, const PlayerLimits& limits,
                        std::string& error) {
    path_ = path;
    scenes_ = std::move(scenes);
    limits_ = limits;
    limits_.keep_every_ticks = std::max<std::uint32_t>(limits_.keep_every_ticks, 1);
    replay::FileSource src;
    if (!src.open(path, error, limits_.max_file_bytes)) return false;
    if (!read(src, error)) {
        error = path + ": " + error;
        return false;
    }
    return true;
}

bool ReplayPlayer::read(replay::ByteSource& src, std::string& error) {
    replay::Scanner scanner(src);
    replay::Event ev;
    WorldState s;
    StepScratch scratch;
    while (scanner.next(ev)) {
        switch (ev.kind) {
            case replay::RecordKind::header:
                if (!on_header(ev, error)) return false;
                s = header_.initial;
                kept_.push_back(s);
                timing_.start(s, static_cast<int>(scene_->track.checkpoints.size()));
                break;
            case replay::RecordKind::tick: on_tick(ev.tick, s, scratch); break;
            case replay::RecordKind::checkpoint:
                if (!on_checkpoint(ev.checkpoint, s, error)) return false;
                break;
            case replay::RecordKind::keyframe: break;  // the checkpoint of the same tick was checked
            case replay::RecordKind::trailer:
                trailer_ = ev.trailer;
                complete_ = true;
                break;
            case replay::RecordKind::signature: break;
        }
    }
    if (scanner.ok()) return true;
    const replay::ScanFailure& f = scanner.failure();
    const bool early_end = f.problem == replay::Problem::incomplete || f.problem == replay::Problem::truncated;
    if (!early_end || scene_ == nullptr) {
        error = std::string(replay::problem_name(f.problem)) + " at byte " + std::to_string(f.byte_offset) + ": " +
                f.message;
        return false;
    }
    warning_ = std::string(replay::problem_name(f.problem)) + ": " + f.message + "; playable up to tick " +
               std::to_string(last_tick());
    return true;
}

bool ReplayPlayer::on_header(const replay::Event& ev, std::string& error) {
    header_ = ev.header;
    scene_ = scenes_(header_, error);
    if (scene_ == nullptr) return false;
    if (header_.track_identity != scene_->track.identity()) {
        error = "recorded on a different track than '" + scene_->track.name + "' (identity mismatch)";
        return false;
    }
    if (header_.physics_hash != physics_fingerprint(scene_->physics)) {
        error = "recorded with other physics settings than this build's";
        return false;
    }
    const auto gates = static_cast<std::int32_t>(scene_->track.checkpoints.size());
    for (const CarState& c : header_.initial.cars) {
        if (c.next_checkpoint >= gates || c.respawn_checkpoint >= gates) {
            error = "the initial state names a gate the track does not have";
            return false;
        }
    }
    slots_ = header_.initial.cars.size();
    return true;
}

void ReplayPlayer::on_tick(const replay::TickRecord& t, WorldState& s, StepScratch& scratch) {
    if (!t.removed.empty()) removed_[ticks_] = t.removed;
    inputs_.insert(inputs_.end(), t.inputs.begin(), t.inputs.end());
    ++ticks_;
    step_one(s, scratch);
    timing_.after_step(s);
    if ((s.tick - first_tick()) % limits_.keep_every_ticks == 0) kept_.push_back(s);
}

bool ReplayPlayer::on_checkpoint(const replay::Checkpoint& c, const WorldState& s, std::string& error) const {
    const replay::Checkpoint mine = replay::checkpoint_of(s);
    if (mine.state_hash == c.state_hash && mine.car_hashes == c.car_hashes) return true;
    error = "the re-simulated world differs from the recording at tick " + std::to_string(s.tick) +
            " (jetrace-sim --diff FILE --rebuild finds where)";
    return false;
}

void ReplayPlayer::step_one(WorldState& s, StepScratch& scratch) const {
    const std::size_t index = s.tick - first_tick();
    if (const auto it = removed_.find(index); it != removed_.end()) {
        for (std::uint8_t slot : it->second) remove_car(s, slot);
    }
    const std::span<const Input> in(inputs_.data() + index * slots_, slots_);
    step(*scene_, s, in, scratch);
}

void ReplayPlayer::seek(WorldState& s, StepScratch& scratch, std::uint32_t tick) const {
    tick = std::clamp(tick, first_tick(), last_tick());
    const bool ours = s.cars.size() == slots_ && s.tick >= first_tick() && s.tick <= tick;
    if (!ours || tick - s.tick > limits_.keep_every_ticks || (complete_ && s.tick == last_tick())) {
        const std::size_t k = (tick - first_tick()) / limits_.keep_every_ticks;
        s = kept_[std::min(k, kept_.size() - 1)];
    }
    while (s.tick < tick) {
        step_one(s, scratch);
        ++steps_taken_;
    }
    // The trailer's removals come after the last tick.
    if (complete_ && s.tick == last_tick()) {
        for (std::uint8_t slot : trailer_.removed) remove_car(s, slot);
    }
}

}  // namespace jetrace::view
