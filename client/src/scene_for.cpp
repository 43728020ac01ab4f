// RaceClient: the scene to race a server's Welcome on (its track, and its
// physics settings, adopted when the core is the same).
#include "jetrace/client/race_client.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>

namespace jetrace::client {

const Scene* RaceClient::scene_for(const proto::Welcome& w, std::string& why) {
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
    if (!adopted_scene_ || adopted_scene_->track.identity() != w.track_identity ||
        proto::physics_hash(adopted_scene_->physics) != w.physics_hash) {
        auto scene = std::make_unique<Scene>(Scene::make(base->track, p));
        scene->broadphase = base->broadphase;
        if (scene_ == adopted_scene_.get()) scene_ = nullptr;  // replaced below
        adopted_scene_ = std::move(scene);
        spdlog::info("{}: adopting the server's physics settings (tick rate {} Hz)", config_.name, p.tick_rate_hz);
    }
    return adopted_scene_.get();
}

}  // namespace jetrace::client
