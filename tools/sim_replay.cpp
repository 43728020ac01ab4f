#include "sim_replay.hpp"

#include "jetrace/auth/key_file.hpp"
#include "jetrace/replay/diff.hpp"
#include "jetrace/replay/scanner.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/replay/synctest.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <cstdio>

namespace jetrace::sim {

namespace {

replay::SceneFor scenes(const ReplayArgs& args) {
    return replay::scene_for([](const std::string& spec, Track& out, std::string& error) { return load_track(spec, out, error); },
                             args.track);
}

bool open(const std::string& path, replay::FileSource& src) {
    std::string error;
    if (src.open(path, error, replay::kMaxFileBytes)) return true;
    std::fprintf(stderr, "jetrace-sim: %s\n", error.c_str());
    return false;
}

bool options_of(const ReplayArgs& args, replay::VerifyOptions& o) {
    o.expect_hash = args.expect;
    if (args.key_file.empty()) return true;
    auth::LoadedKey key;
    std::string error;
    if (!auth::load_key_file(args.key_file, key, error)) {
        std::fprintf(stderr, "jetrace-sim: %s\n", error.c_str());
        return false;
    }
    o.trusted_key = key.public_key;
    return true;
}

}  // namespace

std::optional<std::uint64_t> parse_hash(const std::string& text) {
    if (text.size() != 16) return std::nullopt;
    std::uint64_t v = 0;
    for (char c : text) {
        const int d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
        if (d < 0) return std::nullopt;
        v = v << 4 | static_cast<std::uint64_t>(d);
    }
    return v;
}

int replay_file(const std::string& path, const ReplayArgs& args) {
    replay::FileSource src;
    replay::VerifyOptions o;
    if (!open(path, src) || !options_of(args, o)) return 2;
    const replay::Verdict v = replay::verify(src, scenes(args), o);
    if (v.problem == "track" || v.problem == "physics" || v.problem == "not_a_replay" || v.problem == "old_version") {
        std::fprintf(stderr, "jetrace-sim: %s: %s\n", path.c_str(), v.message.c_str());
        return 2;
    }
    std::printf("replay %s: track %s, race %u, %u ticks, %s\n", path.c_str(), v.track.c_str(), v.race_number,
                v.final_tick - v.initial_tick, v.complete ? v.end_reason.c_str() : "incomplete");
    std::printf("state_hash=%s\n", hash_hex(v.state_hash).c_str());
    if (v.ok) return 0;
    std::fprintf(stderr, "jetrace-sim: %s: %s: %s (byte %llu, tick %u)\n", path.c_str(), v.problem.c_str(),
                 v.message.c_str(), static_cast<unsigned long long>(v.byte_offset), v.tick);
    return 1;
}

int verify_file(const std::string& path, const ReplayArgs& args) {
    replay::FileSource src;
    replay::VerifyOptions o;
    if (!open(path, src) || !options_of(args, o)) return 2;
    const replay::Verdict v = replay::verify(src, scenes(args), o);
    std::printf("%s\n", replay::to_json(v).c_str());
    return v.ok ? 0 : 1;
}

int diff_files(const std::string& a, const std::string& b, const ReplayArgs& args) {
    replay::FileSource sa, sb;
    if (!open(a, sa) || (!b.empty() && !open(b, sb))) return 2;
    const replay::DiffReport d =
        b.empty() ? replay::diff_against_build(replay::verify(sa, scenes(args))) : replay::diff_replays(sa, sb, scenes(args));
    std::printf("%s\n", replay::to_json(d).c_str());
    return d.verdict == "identical" ? 0 : 1;
}

namespace {

void print_state_json(const WorldState& s) {
    std::printf("{\"tick\":%u,\"cars\":[", s.tick);
    const char* sep = "";
    for (std::size_t i = 0; i < s.cars.size(); ++i) {
        const Vec3& p = s.cars[i].position;
        if (!s.cars[i].active) continue;
        std::printf("%s{\"slot\":%zu,\"p\":[%.17g,%.17g,%.17g],\"respawns\":%u}", sep, i, p.x(), p.y(), p.z(),
                    s.cars[i].respawns);
        sep = ",";
    }
    std::printf("]}\n");
}

}  // namespace

int state_at_file(const std::string& path, const ReplayArgs& args, std::uint32_t stop_tick) {
    replay::FileSource src;
    if (!open(path, src)) return 2;
    const replay::SceneFor scene_for = scenes(args);
    replay::Scanner scanner(src);
    replay::Event ev;
    const Scene* scene = nullptr;
    WorldState state;
    StepScratch scratch;
    bool reached = false;
    std::string error;
    while (scanner.next(ev)) {
        if (ev.kind == replay::RecordKind::header) {
            state = ev.header.initial;
            scene = scene_for(ev.header, error);
            if (scene != nullptr && ev.header.track_identity != scene->track.identity()) error = "another track";
            if (scene == nullptr || !error.empty()) break;
            reached = state.tick == stop_tick;
        } else if (ev.kind == replay::RecordKind::tick) {
            if (reached) break;
            for (std::uint8_t slot : ev.tick.removed) remove_car(state, slot);
            step(*scene, state, ev.tick.inputs, scratch);
            reached = state.tick == stop_tick;
        } else if (ev.kind == replay::RecordKind::trailer && reached) {
            for (std::uint8_t slot : ev.trailer.removed) remove_car(state, slot);
        }
    }
    if (!reached) {
        std::fprintf(stderr, "jetrace-sim: %s: no world tick %u in this replay%s%s\n", path.c_str(), stop_tick,
                     error.empty() ? "" : ": ", error.c_str());
        return 2;
    }
    print_state_json(state);
    return 0;
}

int synctest_file(const std::string& path, const ReplayArgs& args) {
    replay::FileSource src;
    if (!open(path, src)) return 2;
    const replay::SynctestReport r = replay::synctest(src, scenes(args), args.rollback_ticks);
    std::printf("%s\n", replay::to_json(r).c_str());
    return r.ok ? 0 : 1;
}

}  // namespace jetrace::sim
