#include "jetrace/replay/scene_for.hpp"

#include <memory>
#include <optional>

namespace jetrace::replay {

SceneFor scene_for(TrackLoader load, std::string track_spec) {
    auto scene = std::make_shared<std::optional<Scene>>();
    return [scene, load = std::move(load), spec = std::move(track_spec)](const Header& h,
                                                                        std::string& error) -> const Scene* {
        if (*scene && (*scene)->physics.tick_rate_hz == h.tick_rate_hz) return &**scene;
        Track track;
        const std::string name = spec.empty() ? h.track_name : spec;
        if (!load(name, track, error)) {
            error += spec.empty() ? " (the replay names this track; give the track file if it is not built in)" : "";
            return nullptr;
        }
        PhysicsSettings physics;
        physics.tick_rate_hz = h.tick_rate_hz;
        if (const std::string e = validate(physics); !e.empty()) {
            error = "the replay's tick rate: " + e;
            return nullptr;
        }
        scene->emplace(Scene::make(std::move(track), physics));
        return &**scene;
    };
}

}  // namespace jetrace::replay
