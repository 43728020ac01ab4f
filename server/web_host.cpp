#include "web_host.hpp"

#include "jetrace/net/mux_transport.hpp"
#include "jetrace/ops/metrics.hpp"
#include "jetrace/proto/close_code.hpp"
#include "jetrace/web/web_site.hpp"

#include <spdlog/spdlog.h>

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
}

bool apply_web(const WebFlags& f, std::size_t pending_cap, std::optional<web::WebConfig>& out) {
    if (f.web.empty()) {
        if (!f.origins.empty() || !f.cert_file.empty() || !f.key_file.empty()) {
            std::fprintf(stderr, "jetrace-server: --web-origin, --web-cert and --web-key need --web\n");
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
    return true;
}

std::unique_ptr<net::Transport> open_web(const web::WebConfig& config, std::unique_ptr<net::Transport> enet,
                                         const net::Transport*& web_part) {
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
    std::printf("web on %s:%u (open %s://%s:%u/ to race from a browser)\n", config.bind.c_str(), port,
                config.cert_file.empty() ? "http" : "https", config.bind == "0.0.0.0" ? "HOST" : config.bind.c_str(),
                port);
    return net::combine(std::move(enet), std::move(web), web::kWebPeerBase);
}

}  // namespace jetrace::server
