#include "jetrace/client/scene_choice.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cassert>

namespace jetrace::client {

SceneChoice::SceneChoice(std::string name, KnownScenes scenes) : name_(std::move(name)), scenes_(std::move(scenes)) {
    assert(!scenes_.empty());
    for (const Scene* s : scenes_) identities_.push_back(s->track.identity());
    current_ = scenes_.front();
}

bool SceneChoice::choose(const proto::Welcome& w, bool& changed, std::string& why) {
    const Scene* chosen = scene_for(w, why);  // current_ is null if it replaced it
    if (chosen == nullptr) return false;
    changed = chosen != current_;
    current_ = chosen;
    return true;
}

bool SceneChoice::knows(std::uint64_t track_identity) const {
    return std::find(identities_.begin(), identities_.end(), track_identity) != identities_.end();
}

void SceneChoice::add(std::unique_ptr<Scene> scene) {
    scenes_.push_back(scene.get());
    identities_.push_back(scene->track.identity());
    downloaded_.push_back(std::move(scene));
}

const Scene* SceneChoice::scene_for(const proto::Welcome& w, std::string& why) {
    const auto known = std::find(identities_.begin(), identities_.end(), w.track_identity);
    if (known == identities_.end()) {
        why = "track mismatch: the server races on '" + w.track_name + "', which differs from ours";
        return nullptr;
    }
    const Scene* base = scenes_[static_cast<std::size_t>(known - identities_.begin())];
    if (w.physics_hash == proto::physics_hash(base->physics)) return base;
    // Other settings (a tick rate of the server's choosing): the same core
    // steps with any valid settings, so adopt the server's if they are
    // what its hash covers (the hash includes the core's revision).
    if (!w.physics || proto::physics_hash(*w.physics) != w.physics_hash) {
        why = "physics settings differ from the server's (not the same physics core)";
        return nullptr;
    }
    const PhysicsSettings& p = *w.physics;
    if (const std::string invalid = validate(p); !invalid.empty()) {
        why = "the server's physics settings are not usable here: " + invalid;
        return nullptr;
    }
    if (!adopted_ || adopted_->track.identity() != w.track_identity ||
        proto::physics_hash(adopted_->physics) != w.physics_hash) {
        auto scene = std::make_unique<Scene>(Scene::make(base->track, p));
        scene->broadphase = base->broadphase;
        if (current_ == adopted_.get()) current_ = nullptr;  // replaced below
        adopted_ = std::move(scene);
        spdlog::info("{}: adopting the server's physics settings (tick rate {} Hz)", name_, p.tick_rate_hz);
    }
    return adopted_.get();
}

}  // namespace jetrace::client
