// jetrace-view: plays recorded races in a browser, watches a live one, or
// drives a car in it. Replay mode loads a replay (and ghost replays of the
// same track), re-simulating each with the shared core; live modes run a
// RaceClient against a jetrace-server: an observer (watch), or a player
// whose car the page's keys drive (--drive NAME).
// Either way it serves the three.js page and streams the world to it over
// a WebSocket (docs/VIEWER.md).
#include "http_server.hpp"
#include "live_session.hpp"
#include "page_messages.hpp"
#include "view_context.hpp"
#include "world_json.hpp"

#include "jetrace/cli/finite.hpp"
#include "jetrace/cli/logging.hpp"
#include "jetrace/proto/messages.hpp"
#include "jetrace/replay/scene_for.hpp"
#include "jetrace/tracks/track_io.hpp"

#include <CLI/CLI.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <spdlog/spdlog.h>

#include <cstdio>

#ifndef JETRACE_VIEW_WEB_DIR
#error "JETRACE_VIEW_WEB_DIR names the page's files (set by client/view/CMakeLists.txt)"
#endif

namespace {

using jetrace::view::ReplayPlayer;

struct Args {
    std::string replay;
    std::string connect;
    std::string drive;
    std::vector<std::string> ghosts;
    std::string track;
    std::string http = "127.0.0.1:8080";
    std::string log_level = "info";
    jetrace::view::ViewSettings settings;
};

std::unique_ptr<ReplayPlayer> load(const std::string& path, const std::string& track) {
    auto p = std::make_unique<ReplayPlayer>();
    std::string error;
    const auto loader = [](const std::string& spec, jetrace::Track& out, std::string& e) {
        return jetrace::load_track(spec, out, e);
    };
    if (!p->load(path, jetrace::replay::scene_for(loader, track), {}, error)) {
        std::fprintf(stderr, "jetrace-view: %s\n", error.c_str());
        return nullptr;
    }
    if (!p->warning().empty()) spdlog::warn("{}: {}", path, p->warning());
    spdlog::info("{}: track {}, ticks {}..{}, {} cars", path, p->scene().track.name, p->first_tick(), p->last_tick(),
                 p->header().initial.cars.size());
    return p;
}

bool load_all(const Args& a, jetrace::view::ViewContext& ctx) {
    ctx.main = load(a.replay, a.track);
    if (!ctx.main) return false;
    for (const std::string& g : a.ghosts) {
        auto ghost = load(g, a.track);
        if (!ghost) return false;
        if (ghost->header().track_identity != ctx.main->header().track_identity ||
            ghost->scene().physics.tick_rate_hz != ctx.main->scene().physics.tick_rate_hz) {
            std::fprintf(stderr, "jetrace-view: --ghost %s: not a replay of the same track at the same tick rate\n",
                         g.c_str());
            return false;
        }
        ctx.ghosts.push_back(std::move(ghost));
    }
    const auto mesh = jetrace::view::track_mesh_bytes(ctx.main->scene().track);
    ctx.track_bin.assign(mesh.begin(), mesh.end());
    return true;
}

void add_options(CLI::App& app, Args& a) {
    namespace v = jetrace::view;
    auto& s = a.settings;
    auto* replay = app.add_option("--replay", a.replay, "the replay to play")->check(CLI::ExistingFile);
    auto* connect = app.add_option("--connect", a.connect, "ADDR:PORT of a jetrace-server: watch its live race as an observer (or drive, with --drive)");
    replay->excludes(connect);
    connect->excludes(replay);
    app.add_option("--drive", a.drive, "with --connect: drive a car named NAME with the page's keys")
        ->needs(connect)
        ->check([](const std::string& n) -> std::string {
            const bool ok = !n.empty() && n.size() <= jetrace::proto::kMaxNameBytes && jetrace::proto::valid_text(n);
            return ok ? "" : "a name of 1 to 32 bytes of UTF-8 without control characters";
        });
    app.add_option("--ghost", a.ghosts, "other replays of the same track, drawn as translucent cars at the same race time")
        ->check(CLI::ExistingFile)
        ->needs(replay);
    app.add_option("--track", a.track, "the track file, when the race's track is not built in (OBJ, glTF or manifest)");
    app.add_option("--http", a.http, "ADDR:PORT to serve the page on (port 0: any free port; the bound address is printed)");
    app.add_option("--frame-rate", s.frame_rate_hz, "frames per second sent to a playing page")
        ->check(CLI::Range(v::kMinFrameRateHz, v::kMaxFrameRateHz));
    app.add_option("--speed", s.speed, "playback speed a page starts at (times real time)")
        ->check(jetrace::cli::finite() & CLI::Range(v::kMinSpeed, v::kMaxSpeed))
        ->needs(replay);
    app.add_option("--max-pages", s.max_pages, "pages (WebSockets) open at once; more are refused")
        ->check(CLI::Range(1, v::kMaxPages));
    app.add_flag("--paused", s.paused, "pages start paused at the first tick (else they play at once)")->needs(replay);
    app.add_option("--web", s.web_dir, "the page's files")->check(CLI::ExistingDirectory);
    app.add_option("--node-modules", s.node_modules_dir, "the node_modules holding three.js (npm ci)")
        ->check(CLI::ExistingDirectory);
    jetrace::cli::add_log_level_option(app, a.log_level);
}

/// Runs the live session's client every millisecond (the bots' pace).
struct LivePump {
    boost::asio::steady_timer timer;
    jetrace::view::LiveSession* live;
    void arm() {
        timer.expires_after(std::chrono::milliseconds(1));
        timer.async_wait([this](const boost::system::error_code& ec) {
            if (ec) return;
            live->update();
            arm();
        });
    }
};

int serve(jetrace::view::ViewContext& ctx) {
    boost::asio::io_context io;
    jetrace::view::HttpServer server(io, ctx);
    std::string error;
    if (!server.listen(ctx.settings.http_host, ctx.settings.http_port, error)) {
        std::fprintf(stderr, "jetrace-view: --http: %s\n", error.c_str());
        return 1;
    }
    const auto ep = server.local_endpoint();
    const std::string host = ep.address().is_v6() ? "[" + ep.address().to_string() + "]" : ep.address().to_string();
    std::printf("listening on http://%s:%u/\n", host.c_str(), static_cast<unsigned>(ep.port()));
    if (std::fflush(stdout) != 0) {
        std::fprintf(stderr, "jetrace-view: cannot write to stdout\n");
        return 1;
    }
    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&io](const boost::system::error_code&, int sig) {
        spdlog::info("signal {}: stopping", sig);
        io.stop();
    });
    server.start();
    LivePump pump{boost::asio::steady_timer(io), ctx.live};
    if (ctx.live) pump.arm();
    io.run();
    return 0;
}

/// "" if the options name one mode: --replay, or --connect with --drive.
std::string mode_error(const Args& a) {
    if (a.replay.empty() && a.connect.empty()) return "--replay FILE or --connect ADDR:PORT is required";
    return "";
}

/// Live: joins the race as a driver (--drive) or an observer, then serves
/// pages (exit 2 for a bad address, 1 if the server cannot be reached or refuses).
int live(const Args& a, jetrace::view::ViewContext& ctx) {
    jetrace::view::LiveOptions o;
    std::string error;
    if (!jetrace::view::parse_http_address(a.connect, o.host, o.port, error) || o.port == 0) {
        if (error.empty()) error = "port 0 is not a server's port";
        std::fprintf(stderr, "jetrace-view: --connect: %s\n", error.c_str());
        return 2;
    }
    o.track_spec = a.track;
    o.drive = !a.drive.empty();
    o.client.name = o.drive ? a.drive : "jetrace-view";
    jetrace::view::LiveSession session;
    if (!session.load_tracks(o, error)) {
        std::fprintf(stderr, "jetrace-view: --track: %s\n", error.c_str());
        return 2;
    }
    if (!session.open(error) || !session.wait_welcome(error)) {
        std::fprintf(stderr, "jetrace-view: %s\n", error.c_str());
        return 1;
    }
    const auto mesh = jetrace::view::track_mesh_bytes(session.client().scene().track);
    ctx.track_bin.assign(mesh.begin(), mesh.end());
    ctx.live = &session;
    const int rc = serve(ctx);
    session.leave("jetrace-view stopped");
    return rc;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-view: watches live races and plays recorded ones in a browser (three.js page, world streamed over a WebSocket)"};
    Args a;
    a.settings.web_dir = JETRACE_VIEW_WEB_DIR;
    a.settings.node_modules_dir = JETRACE_VIEW_NODE_MODULES_DIR;
    add_options(app, a);
    CLI11_PARSE(app, argc, argv);
    jetrace::cli::log_to_stderr("view", a.log_level);
    if (const std::string e = mode_error(a); !e.empty()) {
        std::fprintf(stderr, "jetrace-view: %s\n", e.c_str());
        return 2;
    }
    std::string error;
    if (!jetrace::view::parse_http_address(a.http, a.settings.http_host, a.settings.http_port, error)) {
        std::fprintf(stderr, "jetrace-view: --http: %s\n", error.c_str());
        return 2;
    }
    if (const std::string e = jetrace::view::validate(a.settings); !e.empty()) {
        std::fprintf(stderr, "jetrace-view: %s\n", e.c_str());
        return 2;
    }
    jetrace::view::ViewContext ctx;
    ctx.settings = a.settings;
    if (!a.connect.empty()) return live(a, ctx);
    if (!load_all(a, ctx)) return 2;
    return serve(ctx);
}
