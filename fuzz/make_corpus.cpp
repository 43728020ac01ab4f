// jetrace-fuzz-corpus DIR: writes the generated seed corpus, DIR/<target>/
// gen_*, from real encoders and a real race: every message kind, packed
// payloads, world payloads with and without a baseline, a replay recorded
// by replay::Writer, small OBJ tracks. Deterministic (fixed seeds), so
// re-running it after a format change rewrites the same file names. Files
// not named gen_* (crash inputs kept as regressions) are left alone.
#include "jetrace/ai/driver_ai.hpp"
#include "jetrace/ai/offline_race.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/proto/world_codec.hpp"
#include "jetrace/replay/writer.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"
#include "jetrace/tracks/jtrack.hpp"
#include "jetrace/tracks/track_io.hpp"
#include "packed_payloads.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;
namespace jp = jetrace::proto;
using Bytes = std::vector<std::uint8_t>;

namespace {

fs::path g_root;
int g_files = 0;

void put(const std::string& target, const std::string& name, const Bytes& bytes) {
    const fs::path dir = g_root / target;
    fs::create_directories(dir);
    std::ofstream out(dir / ("gen_" + name), std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!out) {
        std::fprintf(stderr, "jetrace-fuzz-corpus: cannot write %s\n", (dir / name).c_str());
        std::exit(1);
    }
    ++g_files;
}
void put_text(const std::string& target, const std::string& name, const std::string& text) {
    put(target, name, Bytes(text.begin(), text.end()));
}

/// A short AI race on `scene`: the states every `every` ticks.
std::vector<jetrace::WorldState> race_states(const jetrace::Scene& scene, int cars, int samples, int every) {
    jetrace::WorldState state = jetrace::start_race(scene, cars, 2);
    const auto skills = jetrace::skills_for(cars, 7);
    jetrace::StepScratch scratch;
    const jetrace::Course course(scene);
    std::vector<jetrace::WorldState> out;
    for (int i = 0; i < samples; ++i) {
        jetrace::run_ai(course, state, skills, static_cast<std::uint32_t>(every), false, scratch);
        out.push_back(state);
    }
    return out;
}

jp::WorldSnapshot snapshot_of(const jetrace::Scene& scene, const jetrace::WorldState& s) {
    jp::WorldSnapshot w;
    w.state = s;
    w.tick_rate_hz = static_cast<std::uint16_t>(scene.physics.tick_rate_hz);
    const jetrace::Course course(scene);
    for (std::size_t i = 0; i < s.cars.size(); ++i) {
        w.last_inputs.push_back(s.cars[i].active ? jetrace::drive(course, s, static_cast<int>(i)) : jetrace::Input{});
        w.upcoming.emplace_back(i % 3, w.last_inputs.back());
    }
    return w;
}

void messages(const std::vector<Bytes>& worlds, const std::vector<std::uint32_t>& ticks) {
    const std::vector<std::uint8_t> token(jp::kTokenBytes, 0xA5);
    put("message_decode", "hello", jp::encode(jp::Hello{jp::kProtocolVersion, "racer", {}, {}}));
    put("message_decode", "hello_token", jp::encode(jp::Hello{jp::kProtocolVersion, "Zoë", token, {}}));
    const std::vector<std::uint8_t> connect_token(jp::kMaxConnectTokenBytes, 0x5A);
    put("message_decode", "hello_connect_token", jp::encode(jp::Hello{jp::kProtocolVersion, "racer", {}, connect_token}));
    jp::Welcome welcome;
    welcome.slot = 3;
    welcome.max_players = 8;
    welcome.track_name = "ring";
    welcome.track_identity = 0x0123456789abcdefu;
    welcome.physics_hash = 0xfedcba9876543210u;
    welcome.server_tick = 1234;
    welcome.reconnect_token = token;
    put("message_decode", "welcome", jp::encode(welcome));
    put("message_decode", "hello_observe", jp::encode(jp::Hello{jp::kProtocolVersion, "watcher", {}, {}, true}));
    welcome.observer = true;
    welcome.slot = 0;
    welcome.reconnect_token.clear();
    put("message_decode", "welcome_observer", jp::encode(welcome));
    put("message_decode", "snapshot_ack", jp::encode(jp::SnapshotAck{4321}));
    put("message_decode", "refuse", jp::encode(jp::Refuse{"server full"}));
    put("message_decode", "goodbye", jp::encode(jp::Goodbye{"bye"}));
    jp::InputBatch batch;
    batch.first_tick = 500;
    batch.ack_snapshot_tick = 480;
    for (int i = 0; i < 5; ++i) batch.inputs.push_back(jetrace::Input::clamped(15 - i, i * 3 - 6, i == 4));
    put("message_decode", "input_batch", jp::encode(batch));
    put("packed_input_batch", "five", jp::packed::pack(batch));
    batch.inputs.assign(jp::kMaxInputsPerBatch, jetrace::Input::clamped(15, 0, 0));
    batch.ack_snapshot_tick = jp::kNoTick;
    put("packed_input_batch", "full_no_ack", jp::packed::pack(batch));
    for (std::size_t i = 0; i < worlds.size(); ++i) {
        jp::Snapshot snap;
        snap.server_tick = ticks[i];
        snap.baseline_tick = i == 0 ? jp::kNoTick : ticks[i - 1];
        snap.last_applied_input_tick = ticks[i] - 1;
        snap.input_margin_ticks = static_cast<std::int16_t>(i) - 1;
        snap.phase = jp::RacePhase::racing;
        snap.race_number = 2;
        snap.world = worlds[i];
        put("message_decode", "snapshot_" + std::to_string(i), jp::encode(snap));
        put("packed_snapshot", "snapshot_" + std::to_string(i), jp::packed::pack(snap));
    }
    jp::RaceStatus status;
    status.phase = jp::RacePhase::countdown;
    status.race_number = 2;
    status.start_tick = 600;
    status.laps = 3;
    status.players = {{0, "alpha", false}, {5, "beta", true}};
    put("message_decode", "race_status", jp::encode(status));
    jp::Results results;
    results.race_number = 2;
    results.state_hash = 0x1122334455667788u;
    results.standings = {{0, "alpha", true, 3, 71.25}, {5, "beta", false, 2, 0.0}};
    put("message_decode", "results", jp::encode(results));
}

void worlds(const jetrace::Scene& scene) {
    const std::vector<jetrace::WorldState> states = race_states(scene, 4, 4, 90);
    std::vector<jp::WorldSnapshot> snaps;
    for (const auto& s : states) snaps.push_back(snapshot_of(scene, s));
    snaps[1].state.cars[2] = jetrace::CarState{};  // a car that left
    snaps[1].last_inputs[2] = jetrace::Input{};
    std::vector<Bytes> payloads;
    std::vector<std::uint32_t> ticks;
    for (std::size_t i = 0; i < snaps.size(); ++i) {
        const Bytes full = jp::encode_world(snaps[i], nullptr);
        put("world_decode", "full_" + std::to_string(i), full);
        payloads.push_back(i == 0 ? full : jp::encode_world(snaps[i], &snaps[i - 1]));
        ticks.push_back(snaps[i].state.tick);
        if (i == 0) continue;
        const Bytes base = jp::encode_world(snaps[i - 1], nullptr);
        Bytes framed = {static_cast<std::uint8_t>(base.size() & 0xFF), static_cast<std::uint8_t>(base.size() >> 8)};
        framed.insert(framed.end(), base.begin(), base.end());
        framed.insert(framed.end(), payloads.back().begin(), payloads.back().end());
        put("world_decode_delta", "delta_" + std::to_string(i), framed);
    }
    messages(payloads, ticks);
}

void replay(const jetrace::Scene& scene) {
    const fs::path tmp = fs::temp_directory_path() / ("jetrace-fuzz-corpus-" + std::to_string(::getpid()) + ".jtr");
    jetrace::WorldState state = jetrace::start_race(scene, 2, 1);
    jetrace::replay::Header header = jetrace::replay::header_for(scene, state);
    header.checkpoint_every = 4;  // small, so that a short seed has every record kind
    header.keyframe_every = 8;
    header.names = {"alice", "bob"};
    jetrace::replay::Writer writer;
    if (!writer.open(tmp.string(), header)) {
        std::fprintf(stderr, "jetrace-fuzz-corpus: %s\n", writer.error().c_str());
        std::exit(1);
    }
    jetrace::StepScratch scratch;
    const jetrace::Course course(scene);
    for (int t = 0; t < 12; ++t) {
        std::vector<jetrace::Input> inputs;
        for (std::size_t i = 0; i < state.cars.size(); ++i) inputs.push_back(jetrace::drive(course, state, static_cast<int>(i)));
        const std::vector<std::uint8_t> removed = t == 8 ? std::vector<std::uint8_t>{1} : std::vector<std::uint8_t>{};
        writer.record_tick(state.tick, removed, inputs);
        for (std::uint8_t s : removed) jetrace::remove_car(state, s);
        jetrace::step(scene, state, inputs, scratch);
        writer.stepped(state);
    }
    if (!writer.finish(jetrace::replay::trailer_for(scene, state, jetrace::replay::EndReason::aborted))) {
        std::fprintf(stderr, "jetrace-fuzz-corpus: %s\n", writer.error().c_str());
        std::exit(1);
    }
    std::ifstream in(tmp, std::ios::binary);
    const Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    fs::remove(tmp);
    put("replay_parse", "ring_2cars", bytes);
    put("replay_parse", "ring_cut_short", Bytes(bytes.begin(), bytes.end() - 3));
    put("replay_diff", "ring_2cars", bytes);
}

/// An input of fuzz_track_download: the file's size, flags (1: expect the
/// assembled track), then each TrackChunk the server sends for `file` as a
/// u16-length-prefixed message.
Bytes download_input(const Bytes& file) {
    Bytes out;
    const auto size = static_cast<std::uint32_t>(file.size());
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(size >> (8 * i)));
    out.push_back(1);
    for (std::size_t at = 0; at < file.size(); at += jp::kTrackChunkBytes) {
        const std::size_t n = std::min(jp::kTrackChunkBytes, file.size() - at);
        const Bytes msg = jp::encode(jp::TrackChunk{static_cast<std::uint32_t>(at),
                                                    Bytes(file.begin() + static_cast<std::ptrdiff_t>(at),
                                                          file.begin() + static_cast<std::ptrdiff_t>(at + n))});
        out.push_back(static_cast<std::uint8_t>(msg.size()));
        out.push_back(static_cast<std::uint8_t>(msg.size() >> 8));
        out.insert(out.end(), msg.begin(), msg.end());
    }
    return out;
}

void tracks() {
    // The minimal convention (docs/TRACKS.md): floor, two gates, one spawn.
    put_text("obj_import", "minimal.obj",
             "g track\nv -50 0 -50\nv -50 0 50\nv 50 0 50\nv 50 0 -50\nf -4 -3 -2 -1\n"
             "g checkpoint_0\nv 0 0 -10\nv 0 20 -10\nv 0 20 10\nv 0 0 10\nf -4 -3 -2 -1\n"
             "g checkpoint_1\nv 20 0 -5\nv 20 8 -5\nv 20 8 5\nv 20 0 5\nf -4 -3 -2 -1\n"
             "o spawn_0\nv -8 0 0\nv -11 0 1\nv -11 0 -1\nf -3 -2 -1\n"
             "g kill_height\nv -50 -20 -50\nv -50 -20 -49\nv -49 -20 -50\nf -3 -2 -1\n");
    put_text("obj_import", "slashes_comments.obj",
             "# comment\nmtllib none.mtl\no track_floor\nv -30 0 -30 1.0\nv -30 0 30\nv 30 0 30\nv 30 0 -30\n"
             "vt 0 0\nvn 0 1 0\nf 1/1/1 2/1/1 3//1 4//1\n"
             "g checkpoint_0\nv 0 0 -10\nv 0 20 -10\nv 0 20 10\nv 0 0 10\nf 5 6 7\nf 5 7 8\n"
             "g checkpoint_1\nv 10 0 -5\nv 10 8 -5\nv 10 8 5\nv 10 0 5\nf -4 -3 -2 -1\n"
             "g spawn_0\nv -8 0 0\nv -11 0 1\nv -11 0 -1\nf -3 -2 -1\n"
             "g spawn_1\nv -8 0 6\nv -11 0 7\nv -11 0 5\nv -12 0 6\nf -4 -3 -2 -1\n");
    // A small oval through export_obj.
    jetrace::OvalParams p = jetrace::ring_params();
    p.name = "tiny";
    p.straight_m = 100;
    p.turn_radius_m = 40;
    p.turn_segments = 3;
    p.floor_cell_m = 400;
    p.wall = false;
    p.finish_line_m = 50;
    p.spawn_slots = 2;
    const jetrace::Track tiny = jetrace::make_oval(p);
    put_text("obj_import", "tiny_oval.obj", jetrace::export_obj(tiny));
    // The same oval compiled, whole and cut inside its vertices.
    const Bytes compiled = jetrace::encode_jtrack(tiny);
    put("jtrack", "tiny_oval.jtrack", compiled);
    put("jtrack", "tiny_oval_cut.jtrack", Bytes(compiled.begin(), compiled.begin() + 200));
    // The track download: one chunk, and the ring's file in several.
    put("track_download", "tiny_oval", download_input(compiled));
    jetrace::Track ring;
    jetrace::make_builtin_track("ring", ring);
    put("track_download", "ring", download_input(jetrace::encode_jtrack(ring)));
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: jetrace-fuzz-corpus DIR (writes DIR/<target>/gen_*)\n");
        return 2;
    }
    g_root = argv[1];
    jetrace::Track ring;
    if (!jetrace::make_builtin_track("ring", ring)) return 1;
    const jetrace::Scene scene = jetrace::Scene::make(std::move(ring), jetrace::PhysicsSettings{});
    worlds(scene);
    replay(scene);
    tracks();
    std::printf("jetrace-fuzz-corpus: wrote %d files under %s\n", g_files, g_root.c_str());
    return 0;
}
