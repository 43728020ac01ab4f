// The desync finder on untrusted bytes: the input against itself (two
// readings of the same bytes never desync and never differ in inputs), and
// the input against the first half of itself. Invariants: a verdict is
// always one of the documented ones; the same bytes are identical or
// unreadable (or, when incomplete, shorter is impossible: both end alike).
#include "fuzz_check.hpp"
#include "jetrace/replay/diff.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <set>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace jetrace::replay;
    static const SceneFor ring = scene_for(jetrace::load_builtin, "ring");
    static const std::set<std::string> verdicts = {"identical", "inputs_differ", "desync", "different_races",
                                                   "unreadable", "shorter"};
    const auto bytes = jetrace::fuzz::bytes(data, size);
    SpanSource a(bytes), b(bytes);
    const DiffReport same = diff_replays(a, b, ring);
    JETRACE_FUZZ_CHECK(same.verdict == "identical" || same.verdict == "unreadable");
    SpanSource c(bytes), d(bytes.first(size / 2));
    const DiffReport half = diff_replays(c, d, ring);
    JETRACE_FUZZ_CHECK(verdicts.count(half.verdict) == 1);
    JETRACE_FUZZ_CHECK(half.verdict != "desync" && half.verdict != "inputs_differ");
    return 0;
}
