// The WebAssembly client's entry points, called by the page
// (client/view/web/client_source.js): one LiveRace (the same RaceClient,
// prediction and reconciliation as jetrace-bot's) over SocketTransport,
// driven by the page's clock, keys and gamepad, and read back as the same
// hello and frame JSON that jetrace-view sends its pages.
#include "socket_transport.hpp"

#include "json_parts.hpp"
#include "live_json.hpp"
#include "live_race.hpp"

#include "jetrace/replay/scene_for.hpp"
#include "jetrace/replay/source.hpp"
#include "jetrace/replay/verify.hpp"
#include "jetrace/tracks/builtin_tracks.hpp"

#include <emscripten.h>

#include <cmath>
#include <memory>
#include <string>

namespace {

using namespace jetrace;

struct Page {
    std::vector<std::unique_ptr<Scene>> scenes;
    std::unique_ptr<view::LiveRace> race;
    int next_socket = 1;
    std::string text;
    std::vector<std::uint8_t> mesh;
};

Page& page() {
    static Page p;
    return p;
}

std::vector<std::uint8_t> hex_bytes(const char* hex) {
    std::vector<std::uint8_t> out;
    const std::string s = hex != nullptr ? hex : "";
    const auto nibble = [](char c) {
        return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
    };
    if (s.size() % 2 != 0) return {};
    for (std::size_t i = 0; i < s.size(); i += 2) {
        const int hi = nibble(s[i]), lo = nibble(s[i + 1]);
        if (hi < 0 || lo < 0) return {};
        out.push_back(static_cast<std::uint8_t>(hi * 16 + lo));
    }
    return out;
}

bool ready(const view::LiveRace& r) {
    const auto st = r.client().state();
    return st != client::ClientState::connecting && st != client::ClientState::waiting_welcome &&
           st != client::ClientState::closed && !r.client().downloading_track() &&
           (r.client().slot() >= 0 || r.client().observer());
}

}  // namespace

extern "C" {

/// Starts the client (once): `name` drives a car, or watches if `watch`;
/// `token_hex` is a connect token in hex ("" for none). 0 on success, 1 if
/// the token is not hex, 2 if already started.
EMSCRIPTEN_KEEPALIVE int jr_start(const char* name, int watch, const char* token_hex) {
    Page& p = page();
    if (p.race) return 2;
    client::ClientConfig config;
    config.name = name != nullptr ? name : "player";
    config.connect_token = hex_bytes(token_hex);
    if (token_hex != nullptr && token_hex[0] != '\0' && config.connect_token.empty()) return 1;
    const PhysicsSettings physics;
    for (const std::string& n : builtin_track_names()) {
        Track t;
        make_builtin_track(n, t);
        p.scenes.push_back(std::make_unique<Scene>(Scene::make(std::move(t), physics)));
    }
    client::KnownScenes known;
    for (const auto& s : p.scenes) known.push_back(s.get());
    p.race = std::make_unique<view::LiveRace>(config, watch == 0, known, [] {
        return std::make_unique<webclient::SocketTransport>(page().next_socket++);
    });
    return 0;
}

EMSCRIPTEN_KEEPALIVE void jr_socket_opened(int id) {
    if (auto* s = webclient::SocketTransport::find(id)) s->opened();
}
EMSCRIPTEN_KEEPALIVE void jr_socket_frame(int id, const std::uint8_t* data, int size) {
    if (auto* s = webclient::SocketTransport::find(id); s != nullptr && size > 0) s->frame(data, static_cast<std::size_t>(size));
}
EMSCRIPTEN_KEEPALIVE void jr_socket_closed(int id, int code) {
    if (auto* s = webclient::SocketTransport::find(id)) s->closed(code);
}

/// Runs what is due by `now_ms` (the page's performance.now()).
EMSCRIPTEN_KEEPALIVE void jr_update(double now_ms) {
    if (page().race && std::isfinite(now_ms) && now_ms >= 0) page().race->update(static_cast<std::uint64_t>(now_ms * 1000.0));
}

/// The keys held (each 0 or 1).
EMSCRIPTEN_KEEPALIVE void jr_set_keys(int up, int left, int right, int brake) {
    if (!page().race) return;
    view::KeysMessage k;
    k.up = up != 0;
    k.left = left != 0;
    k.right = right != 0;
    k.brake = brake != 0;
    page().race->set_input(view::input_of(k));
}

/// A gamepad's analog input: throttle and steer as fractions in [-1, 1]
/// (clamped; NaN is 0), brake 0 or 1.
EMSCRIPTEN_KEEPALIVE void jr_set_analog(double throttle, double steer, int brake) {
    if (!page().race) return;
    const auto scale = [](double v, int max) {
        if (!std::isfinite(v)) return 0;
        v = v < -1 ? -1 : v > 1 ? 1 : v;
        return static_cast<int>(std::lround(v * max));
    };
    page().race->set_input(Input::clamped(scale(throttle, Input::kMaxThrottle), scale(steer, Input::kMaxSteer), brake != 0 ? 1 : 0));
}

/// 1 once welcomed with the track in hand (the hello can be read).
EMSCRIPTEN_KEEPALIVE int jr_ready() { return page().race && ready(*page().race) ? 1 : 0; }
/// 1 once the client closed (jr_close_code, jr_close_reason say why).
EMSCRIPTEN_KEEPALIVE int jr_closed() {
    return page().race && page().race->client().state() == client::ClientState::closed ? 1 : 0;
}
EMSCRIPTEN_KEEPALIVE int jr_close_code() { return page().race ? page().race->client().close_code() : 0; }
EMSCRIPTEN_KEEPALIVE const char* jr_close_reason() {
    page().text = page().race ? page().race->client().close_reason() : "";
    return page().text.c_str();
}

/// The page messages (UTF-8 JSON, valid until the next call).
EMSCRIPTEN_KEEPALIVE const char* jr_hello() {
    page().text = page().race && ready(*page().race) ? view::live_hello_json(*page().race) : "";
    return page().text.c_str();
}
EMSCRIPTEN_KEEPALIVE const char* jr_frame() {
    page().text = page().race && ready(*page().race) ? view::live_frame_json(*page().race) : "";
    return page().text.c_str();
}
/// The tick the page would show now (a new frame is due when it changes).
EMSCRIPTEN_KEEPALIVE double jr_tick() {
    return page().race && ready(*page().race) ? static_cast<double>(page().race->world().tick) : -1.0;
}

/// The raced track's triangles (view::track_mesh_bytes); `size` gets the length.
EMSCRIPTEN_KEEPALIVE const std::uint8_t* jr_track_mesh(int* size) {
    Page& p = page();
    p.mesh = p.race && ready(*p.race) ? view::track_mesh_bytes(p.race->client().scene().track) : std::vector<std::uint8_t>{};
    *size = static_cast<int>(p.mesh.size());
    return p.mesh.data();
}

/// Says goodbye (the page is closing).
EMSCRIPTEN_KEEPALIVE void jr_leave() {
    if (page().race) page().race->client().leave("page closed");
}

}  // extern "C"

extern "C" {

/// Benchmarks: verifies the replay in `data` (the same re-simulation as
/// jetrace-verify FILE natively) and returns {"ok", "state_hash",
/// "wall_ms", "verdict"} as JSON, timed by the page's clock.
EMSCRIPTEN_KEEPALIVE const char* jr_bench_verify(const std::uint8_t* data, int size) {
    namespace replay = jetrace::replay;
    replay::SpanSource src({data, static_cast<std::size_t>(size > 0 ? size : 0)});
    const double t0 = emscripten_get_now();
    const replay::Verdict v = replay::verify(src, replay::scene_for(jetrace::load_builtin), {});
    const double t1 = emscripten_get_now();
    page().text = "{\"ok\":" + std::string(v.ok ? "true" : "false") + ",\"state_hash\":\"" + jetrace::hash_hex(v.state_hash) +
                  "\",\"wall_ms\":" + std::to_string(t1 - t0) + ",\"verdict\":" + replay::to_json(v) + "}";
    return page().text.c_str();
}

}  // extern "C"
