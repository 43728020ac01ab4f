// The desync finder: two replays of the same race (recorded by two builds,
// or a live recording and a re-simulation) read side by side. It reports
// the first tick whose inputs differ (then the races are not the same) or
// the first checkpoint whose state differs, which cars differ there, the
// fields (by name, both values) at the first keyframe of both at or after
// it, and which of the two this build's core reproduces, re-simulated from
// the last keyframe at which both agreed.
#pragma once

#include "jetrace/replay/verify.hpp"

#include <optional>
#include <string>
#include <vector>

namespace jetrace::replay {

struct DiffReport {
    /// identical, inputs_differ, desync, different_races, unreadable,
    /// or shorter (one ends first, agreeing up to there).
    std::string verdict;
    std::string message;
    std::uint32_t ticks_compared = 0;
    std::optional<std::uint32_t> last_agreeing_tick;
    std::optional<std::uint32_t> first_differing_tick;
    /// Slots whose car hashes differ at first_differing_tick.
    std::vector<int> cars;
    /// A (a) against B (b), at fields_tick.
    std::optional<std::uint32_t> fields_tick;
    std::vector<FieldDifference> fields;
    /// The first tick whose inputs differ, the slot, and the two inputs (packed).
    std::optional<std::uint32_t> input_tick;
    int input_slot = -1;
    std::uint16_t input_a = 0, input_b = 0;
    /// Which recording this build reproduces at first_differing_tick: "a",
    /// "b", "neither", or "" if not re-simulated (unknown track).
    std::string this_build;
};

DiffReport diff_replays(ByteSource& a, ByteSource& b, const SceneFor& scene_for, std::size_t max_fields = 16);

/// `--diff A --rebuild`: A against this build's re-simulation, as a DiffReport.
DiffReport diff_against_build(const Verdict& v);

std::string to_json(const DiffReport& d);

}  // namespace jetrace::replay
