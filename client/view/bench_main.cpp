// jetrace-view-bench: the viewer's figures as one JSON line (docs/VIEWER.md):
// loading a replay (one re-simulation), seeking a fresh page to its last
// tick from the kept states (and to the tick farthest from one) and from
// the start, and the bytes a page
// playing at 1x receives per second (frames as jetrace-view sends them,
// each with its 4-byte WebSocket frame head).
#include "playback.hpp"
#include "world_json.hpp"

#include "jetrace/cli/finite.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace {

using Clock = std::chrono::steady_clock;
using jetrace::view::ReplayPlayer;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

bool load(const std::string& path, std::uint32_t keep_every, ReplayPlayer& p) {
    const auto loader = [](const std::string& spec, jetrace::Track& out, std::string& e) {
        return jetrace::load_track(spec, out, e);
    };
    jetrace::view::PlayerLimits limits;
    limits.keep_every_ticks = keep_every;
    std::string error;
    if (p.load(path, jetrace::replay::scene_for(loader), limits, error)) return true;
    std::fprintf(stderr, "jetrace-view-bench: %s\n", error.c_str());
    return false;
}

double median_seek_ms(const ReplayPlayer& p, std::uint32_t tick, int repeats) {
    std::vector<double> ms;
    for (int i = 0; i < repeats; ++i) {
        jetrace::view::Playback pb(p, {});
        const auto t0 = Clock::now();
        pb.seek(tick);
        ms.push_back(ms_since(t0));
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

/// Bytes per second of real time of a page playing the whole replay at 1x.
double stream_bytes_per_s(const ReplayPlayer& p, int frame_rate_hz) {
    jetrace::view::Playback pb(p, {});
    pb.set_playing(true);
    double bytes = 0;
    std::uint64_t frames = 0;
    while (pb.playing()) {
        pb.advance(1.0 / frame_rate_hz);
        bytes += static_cast<double>(jetrace::view::frame_json(pb).size()) + 4;
        ++frames;
    }
    return frames == 0 ? 0 : bytes / (static_cast<double>(frames) / frame_rate_hz);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-view-bench: load, seek and stream figures of jetrace-view on one replay (JSON)"};
    std::string path;
    int repeats = 5, frame_rate = 30;
    app.add_option("--replay", path, "the replay")->required()->check(CLI::ExistingFile);
    app.add_option("--repeats", repeats, "seeks timed (the median is printed)")->check(CLI::Range(1, 1000));
    app.add_option("--frame-rate", frame_rate, "frames per second of the stream")->check(CLI::Range(1, 120));
    CLI11_PARSE(app, argc, argv);

    ReplayPlayer kept, from_start;
    auto t0 = Clock::now();
    if (!load(path, jetrace::view::PlayerLimits{}.keep_every_ticks, kept)) return 2;
    const double load_ms = ms_since(t0);
    if (!load(path, 0xFFFFFFFFu, from_start)) return 2;
    // The costliest seek: the last tick one short of a kept state.
    const std::uint32_t keep = jetrace::view::PlayerLimits{}.keep_every_ticks;
    const std::uint32_t span = kept.last_tick() - kept.first_tick();
    const std::uint32_t worst = span < keep ? kept.last_tick() : kept.first_tick() + (span / keep) * keep - 1;
    nlohmann::json j = {{"replay", path},
                        {"cars", kept.header().initial.cars.size()},
                        {"ticks", kept.last_tick() - kept.first_tick()},
                        {"load_ms", load_ms},
                        {"keep_every_ticks", keep},
                        {"seek_end_ms_median", median_seek_ms(kept, kept.last_tick(), repeats)},
                        {"seek_worst_tick", worst},
                        {"seek_worst_ms_median", median_seek_ms(kept, worst, repeats)},
                        {"seek_end_from_start_ms_median", median_seek_ms(from_start, from_start.last_tick(), repeats)},
                        {"hello_bytes", jetrace::view::hello_json(jetrace::view::Playback(kept, {})).size()},
                        {"frame_rate_hz", frame_rate},
                        {"ws_bytes_per_s_per_page", stream_bytes_per_s(kept, frame_rate)}};
    std::printf("%s\n", j.dump().c_str());
    return std::fflush(stdout) == 0 ? 0 : 1;
}
