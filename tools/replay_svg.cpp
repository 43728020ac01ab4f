#include "replay_svg.hpp"

#include "jetrace/replay/scanner.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/tracks/track_io.hpp"
#include "track/track_svg.hpp"

#include <cstdio>
#include <fstream>

namespace jetrace::sim {

namespace {

/// A point of each car's line every this many ticks (unit: ticks).
constexpr std::uint32_t kSampleTicks = 6;

struct Drawing {
    const Scene* scene = nullptr;
    TrackReport report;
    std::vector<tools::SvgTrace> traces;
};

bool on_header(const replay::Header& h, const ReplayArgs& args, const replay::SceneFor& scenes, Drawing& d,
               std::string& error) {
    d.scene = scenes(h, error);
    if (d.scene == nullptr) return false;
    if (h.track_identity != d.scene->track.identity()) {
        error = "recorded on a different track than '" + d.scene->track.name + "'";
        return false;
    }
    Track again;  // the report (the route) comes with inspecting the track
    if (!inspect_track(args.track.empty() ? h.track_name : args.track, again, d.report, error)) return false;
    for (std::size_t s = 0; s < h.initial.cars.size(); ++s) {
        const bool named = s < h.names.size() && !h.names[s].empty();
        d.traces.push_back({named ? h.names[s] : "car " + std::to_string(s), {}, {}});
    }
    return true;
}

void sample(const WorldState& s, Drawing& d) {
    for (std::size_t i = 0; i < s.cars.size() && i < d.traces.size(); ++i) {
        if (!s.cars[i].active) continue;
        d.traces[i].points.push_back(s.cars[i].position);
        d.traces[i].speeds_mps.push_back(s.cars[i].velocity.norm());
    }
}

}  // namespace

int svg_file(const std::string& path, const ReplayArgs& args, const std::string& svg_path, int width_px) {
    replay::FileSource src;
    std::string error;
    if (!src.open(path, error, replay::kMaxFileBytes)) {
        std::fprintf(stderr, "jetrace-sim: %s\n", error.c_str());
        return 2;
    }
    const replay::SceneFor scenes = replay::scene_for(
        [](const std::string& spec, Track& out, std::string& e) { return load_track(spec, out, e); }, args.track);
    replay::Scanner scanner(src);
    replay::Event ev;
    Drawing d;
    WorldState state;
    StepScratch scratch;
    while (scanner.next(ev)) {
        if (ev.kind == replay::RecordKind::header) {
            if (!on_header(ev.header, args, scenes, d, error)) {
                std::fprintf(stderr, "jetrace-sim: %s: %s\n", path.c_str(), error.c_str());
                return 2;
            }
            state = ev.header.initial;
            sample(state, d);
        } else if (ev.kind == replay::RecordKind::tick) {
            for (std::uint8_t slot : ev.tick.removed) remove_car(state, slot);
            step(*d.scene, state, ev.tick.inputs, scratch);
            if (state.tick % kSampleTicks == 0) sample(state, d);
        }
    }
    if (!scanner.ok()) {
        const replay::ScanFailure& f = scanner.failure();
        const bool early = f.problem == replay::Problem::incomplete || f.problem == replay::Problem::truncated;
        std::fprintf(stderr, "jetrace-sim: %s: %s: %s%s\n", path.c_str(), replay::problem_name(f.problem),
                     f.message.c_str(), early ? " (drawn up to there)" : "");
        if (!early || d.scene == nullptr) return d.scene == nullptr ? 2 : 1;
    }
    std::ofstream out(svg_path, std::ios::binary);
    out << tools::render_svg(d.scene->track, d.report, width_px, d.traces);
    out.close();
    if (!out) {
        std::fprintf(stderr, "jetrace-sim: cannot write %s\n", svg_path.c_str());
        return 1;
    }
    std::printf("wrote %s: %zu cars up to tick %u\n", svg_path.c_str(), d.traces.size(), state.tick);
    return 0;
}

}  // namespace jetrace::sim
