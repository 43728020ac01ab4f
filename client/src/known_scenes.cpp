// The tracks a client program knows: files through the importers
// (jetrace::tracks), or the built-in ones. Apart from scene_choice.cpp so
// that the WebAssembly client, which reads no files, builds without them.
#include "jetrace/client/scene_choice.hpp"

#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/track_io.hpp"

namespace jetrace::client {

bool load_known_scenes(const std::string& track_spec, std::vector<std::unique_ptr<Scene>>& out, std::string& error) {
    const PhysicsSettings physics;
    if (!track_spec.empty()) {
        Track t;
        if (!load_track(track_spec, t, error)) return false;
        out.push_back(std::make_unique<Scene>(Scene::make(std::move(t), physics)));
        return true;
    }
    for (const std::string& name : builtin_track_names()) {
        Track t;
        make_builtin_track(name, t);
        out.push_back(std::make_unique<Scene>(Scene::make(std::move(t), physics)));
    }
    return true;
}

}  // namespace jetrace::client
