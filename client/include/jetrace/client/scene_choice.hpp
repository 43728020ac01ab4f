// The scene a client races on: the known track the server's Welcome names,
// with the server's physics settings adopted when they are the same core's
// (docs/PROTOCOL.md, "Checking the Welcome").
#pragma once

#include "jetrace/core/world.hpp"
#include "jetrace/proto/messages.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace jetrace::client {

/// The tracks a client can race on (each outlives the client; at least one).
/// The server's Welcome names its track by identity: the client races on the
/// one that matches, and leaves if none does.
using KnownScenes = std::vector<const Scene*>;

/// The tracks a client program knows, with default physics: the track file
/// `track_spec` only (OBJ, glTF, manifest or .jtrack), or every built-in
/// track when it is empty. False with `error` if the file cannot be loaded.
bool load_known_scenes(const std::string& track_spec, std::vector<std::unique_ptr<Scene>>& out, std::string& error);

class SceneChoice {
public:
    /// `name`: the client's, for log lines.
    SceneChoice(std::string name, KnownScenes scenes);

    /// The scene raced on: the one the last Welcome chose (before one, the
    /// first known one).
    const Scene& current() const { return *current_; }
    /// Races on the scene for `w` from now on; false with `why` if there is
    /// none (the current one stays). `changed`: another scene than before.
    bool choose(const proto::Welcome& w, bool& changed, std::string& why);
    /// Whether a known scene has a track of this identity.
    bool knows(std::uint64_t track_identity) const;
    /// Knows `scene` from now on (a track downloaded from the server).
    void add(std::unique_ptr<Scene> scene);

private:
    /// The scene for `w`, or nullptr with `why`.
    const Scene* scene_for(const proto::Welcome& w, std::string& why);

    std::string name_;
    KnownScenes scenes_;
    std::vector<std::uint64_t> identities_;  // Track::identity() of each
    std::vector<std::unique_ptr<Scene>> downloaded_;  // add()ed: in scenes_ too
    const Scene* current_ = nullptr;
    /// A known scene rebuilt with the server's physics settings (Welcome),
    /// if they differ from the known scene's.
    std::unique_ptr<Scene> adopted_;
};

}  // namespace jetrace::client
