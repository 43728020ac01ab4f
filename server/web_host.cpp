#include "web_host.hpp"

#include "jetrace/net/mux_transport.hpp"
#include "jetrace/ops/metrics.hpp"
#include "jetrace/proto/close_code.hpp"
#include "jetrace/web/web_site.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>

namespace jetrace::server {

// The web transport closes sockets with the protocol's own codes.
static_assert(web::kMalformedFrame == static_cast<std::uint16_t>(proto::CloseCode::malformed));
static_assert(web::kSendQueueFull == static_cast<std::uint16_t>(proto::CloseCode::send_queue_full));

void add_web_options(CLI::App& app, WebFlags& f) {
    app.add_option("--web", f.web,
                   "serve the game page and browser players (WebSocket) on ADDR:PORT (PORT alone: 127.0.0.1; 0: any "
                   "port)");
    app.add_option("--web-origin", f.origins,
                   "an origin (http[s]://HOST[:PORT]) whose pages may join besides the server's own page; repeatable");
    app.add_option("--web-max-sockets", f.max_sockets, "most browser game sockets open at once")
        ->check(CLI::Range(1, 100000));
    app.add_option("--web-cert", f.cert_file, "serve --web over TLS (HTTPS, WSS) with this PEM certificate chain")
        ->check(CLI::ExistingFile);
    app.add_option("--web-key", f.key_file, "the PEM private key of --web-cert")->check(CLI::ExistingFile);
    app.add_option("--webrtc-port", f.webrtc_port,
                   "UDP port of browser players' WebRTC data channels, on --web's address (default: --web's port "
                   "number; 0: any)")
        ->check(CLI::Range(0, 65535));
    app.add_option("--webrtc-address", f.webrtc_address,
                   "the IP address the SDP answer gives browsers for --webrtc-port (default: the address their page "
                   "reached --web at)");
    app.add_option("--webrtc-candidate-port", f.webrtc_candidate_port,
                   "the UDP port the SDP answer gives browsers (behind a port forward: the public one; default: "
                   "--webrtc-port)")
        ->check(CLI::Range(1, 65535));
    app.add_flag("--no-webrtc", f.no_webrtc, "browsers race over WebSocket only: no WebRTC data channels");
    app.add_option("--web-link", f.web_link,
                   "network conditions on browser players' links, both directions, on the server's clock: "
                   "NAME=VALUE,... with latency, jitter (ms), loss, dup, reorder (probabilities), rate (kbit/s), "
                   "retransmit (ms; default 1.25 round trips, at least 20): what jetrace-netsim does to ENet "
                   "(tests, measurements)");
}

bool apply_web(const WebFlags& f, std::size_t pending_cap, std::optional<web::WebConfig>& out,
               std::optional<rtc::RtcConfig>& rtc, std::optional<net::Conditions>& link) {
    if (f.web.empty()) {
        if (!f.origins.empty() || !f.cert_file.empty() || !f.key_file.empty() || f.webrtc_port >= 0 ||
            !f.webrtc_address.empty() || f.webrtc_candidate_port != 0 || f.no_webrtc || !f.web_link.empty()) {
            std::fprintf(stderr, "jetrace-server: --web-origin, --web-cert, --web-key, --web-link and the --webrtc "
                         "flags need --web\n");
            return false;
        }
        return true;
    }
    web::WebConfig c;
    int port = 0;
    std::string error;
    if (!ops::parse_host_port(f.web, c.bind, port, error)) {
        std::fprintf(stderr, "jetrace-server: --web: %s\n", error.c_str());
        return false;
    }
    c.port = static_cast<std::uint16_t>(port);
    c.origins = f.origins;
    c.max_sockets = f.max_sockets;
    c.max_pending_per_address = pending_cap;
    c.cert_file = f.cert_file;
    c.key_file = f.key_file;
    if (error = web::validate(c); !error.empty()) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return false;
    }
    out = c;
    if (!f.web_link.empty()) {
        link = parse_web_link(f.web_link, error);
        if (!link) {
            std::fprintf(stderr, "jetrace-server: --web-link: %s\n", error.c_str());
            return false;
        }
    }
    if (f.no_webrtc) return true;
    rtc::RtcConfig r;
    r.bind = c.bind;
    r.port = static_cast<std::uint16_t>(f.webrtc_port >= 0 ? f.webrtc_port : c.port);
    r.candidate_ip = f.webrtc_address;
    r.candidate_port = static_cast<std::uint16_t>(f.webrtc_candidate_port);
    r.max_pending_per_address = std::max<std::size_t>(1, std::min<std::size_t>(pending_cap == 0 ? 4 : pending_cap, 16));
    r.peer_base = rtc::kRtcPeerBase;
    if (error = rtc::validate(r); !error.empty()) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return false;
    }
    rtc = r;
    return true;
}

namespace {

/// Binds the WebRTC UDP port and points `config`'s POST /rtc at it; null
/// after printing why it cannot.
std::unique_ptr<net::Transport> open_rtc(const rtc::RtcConfig& r, web::WebConfig& config) {
    std::shared_ptr<rtc::RtcSignal> signal;
    std::string error;
    auto t = rtc::listen_rtc(r, signal, error);
    if (!t) {
        std::fprintf(stderr, "jetrace-server: --webrtc-port: %s\n", error.c_str());
        return nullptr;
    }
    config.rtc_signal = [signal](std::string_view offer, const std::string& address, const std::string& local_ip) {
        const rtc::RtcReply reply = signal->offer(offer, address, local_ip);
        return web::SignalReply{reply.status, reply.content_type, reply.body};
    };
    std::printf("webrtc on %s:%u (UDP: browsers' data channels)\n", r.bind.c_str(), t->local_port());
    return t;
}

}  // namespace

std::unique_ptr<net::Transport> open_web(web::WebConfig config, const std::optional<rtc::RtcConfig>& rtc,
                                         std::unique_ptr<net::Transport> enet, const net::Transport*& web_part,
                                         const net::Transport*& rtc_part, WebLink* link) {
    std::unique_ptr<net::Transport> datachannels;
    if (rtc) {
        datachannels = open_rtc(*rtc, config);
        if (!datachannels) return nullptr;
        rtc_part = datachannels.get();
        if (link) datachannels = link->wrap_webrtc(std::move(datachannels));
    }
    std::vector<std::string> missing;
    web::WebSite site = web::load_site({JETRACE_WEB_PAGE_DIR, JETRACE_NODE_MODULES_DIR, JETRACE_WEB_CLIENT_DIR}, missing);
    for (const std::string& m : missing) {
        spdlog::warn("web: {} is missing: the page will not load (tools/build.sh builds the WebAssembly client, "
                     "tools/setup.sh installs three.js)", m);
    }
    std::uint16_t port = 0;
    std::string error;
    auto web = web::listen_web(config, std::move(site), port, error);
    if (!web) {
        std::fprintf(stderr, "jetrace-server: %s\n", error.c_str());
        return nullptr;
    }
    web_part = web.get();
    if (link) web = link->wrap_websocket(std::move(web));
    std::printf("web on %s:%u (open %s://%s:%u/ to race from a browser)\n", config.bind.c_str(), port,
                config.cert_file.empty() ? "http" : "https", config.bind == "0.0.0.0" ? "HOST" : config.bind.c_str(),
                port);
    auto both = net::combine(std::move(enet), std::move(web), web::kWebPeerBase);
    if (!datachannels) return both;
    return net::combine(std::move(both), std::move(datachannels), rtc::kRtcPeerBase, "webrtc");
}

}  // namespace jetrace::server
