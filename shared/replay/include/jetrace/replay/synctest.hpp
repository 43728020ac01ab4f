// SyncTest (after GGRS's): re-simulates a replay and, at every tick, steps
// a copy of the saved state again in a fresh world with fresh scratch and
// compares the two bit for bit; every `rollback_ticks` ticks it also rolls
// back that many ticks and re-simulates them with the live scratch, as a
// predicting client does. Any difference is state kept outside WorldState.
#pragma once

#include "jetrace/replay/verify.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace jetrace::replay {

struct SynctestReport {
    bool ok = false;
    std::uint64_t ticks = 0;
    std::uint64_t fresh_checks = 0;
    std::uint64_t rollback_checks = 0;
    int rollback_ticks = 0;
    /// On failure: "fresh_scratch", "rollback", or "replay" (unreadable).
    std::string check;
    std::uint32_t tick = 0;
    std::string message;
    /// The first run (a) against the second (b).
    std::vector<FieldDifference> fields;
};

/// `rollback_ticks` in [1, 240].
SynctestReport synctest(ByteSource& source, const SceneFor& scene_for, int rollback_ticks = 8);

std::string to_json(const SynctestReport& r);

}  // namespace jetrace::replay
