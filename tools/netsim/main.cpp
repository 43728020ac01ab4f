// jetrace-netsim: a UDP proxy that puts latency, jitter, loss, duplication,
// reordering and a bandwidth limit between clients and a server.
//
//   jetrace-netsim --listen 27911 --forward 127.0.0.1:27910 --latency 35 --jitter 30 --loss 0.05
//
// Each condition applies to both directions unless given per direction
// (--up-loss: client -> server, --down-loss: server -> client). On SIGINT,
// SIGTERM or after --duration it prints one JSON line of counters.
#include "jetrace/cli/finite.hpp"
#include "jetrace/cli/logging.hpp"
#include "jetrace/net/address.hpp"
#include "jetrace/net/condition_spec.hpp"
#include "jetrace/net/link_conditions.hpp"
#include "jetrace/proto/messages.hpp"
#include "udp_proxy.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <optional>

namespace {

std::atomic<int> g_signal{0};
void on_signal(int sig) { g_signal = sig; }

// One condition as options: --NAME (both directions), --up-NAME, --down-NAME.
struct ConditionOption {
    const jetrace::net::ConditionField* field;
    std::optional<double> both, up, down;
};

nlohmann::json to_json(const jetrace::netsim::DirectionCounters& d) {
    return {{"received", d.received},         {"forwarded", d.forwarded},   {"forwarded_bytes", d.forwarded_bytes},
            {"dropped", d.scheduler.dropped},           {"duplicated", d.scheduler.duplicated},
            {"reordered", d.scheduler.reordered},       {"rate_limited", d.scheduler.rate_limited},
            {"send_failed", d.send_failed},             {"pending", d.pending}};
}

// The input ticks of the jetrace InputBatch inside an ENet datagram: ENet
// puts a command's 16-bit big-endian data length right before its data,
// and a packed InputBatch starts with 4 zero bytes and "JINP".
std::optional<jetrace::net::SequenceRange> enet_input_ticks(std::span<const std::uint8_t> datagram) {
    static constexpr std::uint8_t kMagic[8] = {0, 0, 0, 0, 'J', 'I', 'N', 'P'};
    for (std::size_t at = 2; at + sizeof kMagic <= datagram.size(); ++at) {
        if (std::memcmp(datagram.data() + at, kMagic, sizeof kMagic) != 0) continue;
        const std::size_t length = (std::size_t{datagram[at - 2]} << 8) | datagram[at - 1];
        if (at + length > datagram.size()) continue;
        jetrace::net::SequenceRange r;
        if (jetrace::proto::input_batch_ticks(datagram.subspan(at, length), r.first, r.last)) return r;
    }
    return std::nullopt;
}

nlohmann::json delay_json(const std::vector<double>& delays) {
    return {{"n", delays.size()},
            {"p50", jetrace::net::quantile(delays, 0.5)},
            {"p99", jetrace::net::quantile(delays, 0.99)},
            {"max", jetrace::net::quantile(delays, 1.0)}};
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"jetrace-netsim: a UDP proxy that degrades the traffic between clients and a server"};
    jetrace::netsim::ProxyConfig cfg;
    int listen_port = -1;
    std::string forward;
    std::uint64_t seed = 1;
    double duration_s = 0;
    std::string log_level = "warn";
    app.add_option("--listen", listen_port, "UDP port for clients (0: any free port, printed at start)")
        ->required()
        ->check(CLI::Range(0, 65535));
    app.add_option("--bind", cfg.bind, "address to listen on (IPv4)");
    app.add_option("--forward", forward, "the server, HOST:PORT")->required();
    std::vector<ConditionOption> conditions;
    for (const jetrace::net::ConditionField& f : jetrace::net::condition_fields()) {
        // A UDP proxy sees no reliable datagrams: every one it drops stays dropped.
        if (std::string_view(f.name) != "retransmit") conditions.push_back({&f, {}, {}, {}});
    }
    for (ConditionOption& o : conditions) {
        const CLI::Validator range = jetrace::cli::finite() & CLI::Range(o.field->lo, o.field->hi);
        const std::string name = o.field->name;
        const std::string help = o.field->help;
        app.add_option("--" + name, o.both, help + ", both directions")->check(range);
        app.add_option("--up-" + name, o.up, help + ", client -> server")->check(range);
        app.add_option("--down-" + name, o.down, help + ", server -> client")->check(range);
    }
    app.add_option("--seed", seed, "seed of the random choices");
    app.add_option("--duration", duration_s, "exit after this many seconds (0: run until SIGINT/SIGTERM)")
        ->check(jetrace::cli::finite() & CLI::Range(0.0, 1e7));
    app.add_option("--idle-timeout", cfg.idle_timeout_s, "forget a client silent for this long (s)")
        ->check(jetrace::cli::finite() & CLI::Range(1.0, 86400.0));
    app.add_option("--max-clients", cfg.max_clients, "most clients served at once")->check(CLI::Range(1, 4096));
    jetrace::cli::add_log_level_option(app, log_level);
    CLI11_PARSE(app, argc, argv);
    jetrace::cli::log_to_stderr("netsim", log_level);

    if (!jetrace::net::split_host_port(forward, cfg.forward_host, cfg.forward_port)) {
        std::fprintf(stderr, "jetrace-netsim: --forward must be HOST:PORT, got '%s'\n", forward.c_str());
        return 2;
    }
    cfg.port = static_cast<std::uint16_t>(listen_port);
    for (const ConditionOption& o : conditions) {
        const auto member = o.field->field;
        if (o.both) cfg.up.*member = cfg.down.*member = *o.both;
        if (o.up) cfg.up.*member = *o.up;
        if (o.down) cfg.down.*member = *o.down;
    }
    cfg.up.seed = seed;
    cfg.down.seed = seed ^ 0x9E3779B97F4A7C15ull;

    std::string error;
    auto proxy = jetrace::netsim::UdpProxy::open(cfg, error);
    if (!proxy) {
        std::fprintf(stderr, "jetrace-netsim: %s\n", error.c_str());
        return 1;
    }
    jetrace::net::SequenceDelayMeter input_delay(enet_input_ticks);
    proxy->observe_up(&input_delay);
    std::printf("listening on %s:%u\n", cfg.bind.c_str(), proxy->local_port());
    std::fflush(stdout);
    spdlog::info("forwarding to {}:{}; up: {} ms + [0, {}] ms, loss {}, rate {} kbit/s; down: {} ms + [0, {}] ms, "
                 "loss {}, rate {} kbit/s",
                 cfg.forward_host, cfg.forward_port, cfg.up.latency_ms, cfg.up.jitter_ms, cfg.up.loss,
                 cfg.up.rate_kbps, cfg.down.latency_ms, cfg.down.jitter_ms, cfg.down.loss, cfg.down.rate_kbps);

    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const auto start = std::chrono::steady_clock::now();
    int rc = 0;
    while (g_signal == 0) {
        if (duration_s > 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= duration_s)
            break;
        if (!proxy->step(50)) {
            rc = 1;
            break;
        }
    }
    const auto c = proxy->counters();
    nlohmann::json j;
    j["up"] = to_json(c.up);
    j["down"] = to_json(c.down);
    // Client -> server: from the first datagram carrying an input tick to
    // the first one forwarded with it (lost ones included: redundancy).
    if (!input_delay.delays_ms().empty()) j["up"]["input_delay_ms"] = delay_json(input_delay.delays_ms());
    j["clients"] = c.clients;
    j["clients_expired"] = c.clients_expired;
    j["clients_refused"] = c.clients_refused;
    j["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s\n", j.dump().c_str());
    std::fflush(stdout);
    return rc;
}
