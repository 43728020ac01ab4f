// AgonesClient: Ready, Health, Shutdown and the GameServer watch over the
// SDK sidecar's REST gateway, on two threads of its own.
#include "jetrace/ops/agones_client.hpp"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <algorithm>

namespace jetrace::ops {

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

Clock::duration seconds(double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

/// A watch line longer than this is not a GameServer: reconnect.
constexpr std::size_t kMaxWatchLine = 1 << 20;

}  // namespace

AgonesClient::AgonesClient(AgonesConfig config) : config_(std::move(config)) {}

AgonesClient::~AgonesClient() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
        if (watch_client_) watch_client_->stop();
    }
    wake_.notify_all();
    if (worker_.joinable()) worker_.join();
    if (watcher_.joinable()) watcher_.join();
}

void AgonesClient::start() {
    const auto now = Clock::now().time_since_epoch().count();
    heartbeat_ = now;
    last_contact_ = now;
    worker_ = std::thread([this] { work(); });
    watcher_ = std::thread([this] { watch(); });
}

void AgonesClient::heartbeat() { heartbeat_ = Clock::now().time_since_epoch().count(); }

std::optional<GameServerView> AgonesClient::allocation() const {
    std::lock_guard lock(mutex_);
    return allocation_;
}

std::string AgonesClient::failure() const {
    std::lock_guard lock(mutex_);
    return failure_;
}

void AgonesClient::fail(const std::string& why) {
    std::lock_guard lock(mutex_);
    if (!failure_.empty()) return;
    failure_ = why;
    spdlog::error("agones: {}", why);
}

bool AgonesClient::pause(Clock::duration d) {
    std::unique_lock lock(mutex_);
    wake_.wait_for(lock, d, [this] { return stopping_ || shutdown_wanted_; });
    return !stopping_;
}

bool AgonesClient::post(httplib::Client& cli, const char* path, std::string& error) {
    const httplib::Result res = cli.Post(path, "{}", "application/json");
    if (!res) {
        error = "POST " + std::string(path) + ": " + httplib::to_string(res.error());
        return false;
    }
    if (res->status != 200) {
        error = "POST " + std::string(path) + ": HTTP " + std::to_string(res->status);
        return false;
    }
    last_contact_ = Clock::now().time_since_epoch().count();
    return true;
}

void AgonesClient::try_ready(httplib::Client& cli, Clock::time_point started) {
    std::string error;
    if (post(cli, "/ready", error)) {
        ready_ = true;
        outage_logged_ = false;
        spdlog::info("agones: Ready (sidecar at {}:{})", config_.host, config_.port);
        return;
    }
    if (Clock::now() - started > seconds(config_.connect_timeout_s)) {
        fail(fmt::format("no Agones sidecar answered at {}:{} within {} s ({})", config_.host, config_.port,
                         config_.connect_timeout_s, error));
    } else if (!outage_logged_) {
        spdlog::info("agones: sidecar not answering yet ({}); retrying for {} s", error, config_.connect_timeout_s);
        outage_logged_ = true;
    }
}

void AgonesClient::ping_health(httplib::Client& cli) {
    const auto now = Clock::now();
    const auto period = seconds(config_.health_period_s);
    // Health reflects the tick loop: no heartbeat, no ping.
    const auto beat = Clock::time_point(Clock::duration(heartbeat_.load()));
    std::string error;
    if (now - beat > std::max<Clock::duration>(3 * period, 1s)) {
        spdlog::warn("agones: the server loop is stalled; no Health ping");
    } else if (post(cli, "/health", error)) {
        if (outage_logged_) spdlog::info("agones: sidecar answering again");
        outage_logged_ = false;
    } else if (!outage_logged_) {
        spdlog::warn("agones: Health failed ({}); retrying", error);
        outage_logged_ = true;
    }
    const auto contact = Clock::time_point(Clock::duration(last_contact_.load()));
    if (now - contact > seconds(config_.connect_timeout_s)) {
        fail(fmt::format("the Agones sidecar has not answered for {} s", config_.connect_timeout_s));
    }
}

void AgonesClient::send_shutdown(httplib::Client& cli) {
    std::string error;
    bool ok = false;
    for (int attempt = 0; !ok && attempt < 20; ++attempt) {
        ok = post(cli, "/shutdown", error);
        if (!ok) {
            std::unique_lock lock(mutex_);
            if (wake_.wait_for(lock, 100ms, [this] { return stopping_; })) break;
        }
    }
    if (ok) {
        spdlog::info("agones: Shutdown");
    } else {
        spdlog::error("agones: Shutdown not acknowledged ({})", error);
    }
    std::lock_guard lock(mutex_);
    shutdown_done_ = true;
    shutdown_ok_ = ok;
    wake_.notify_all();
}

void AgonesClient::work() {
    httplib::Client cli(config_.host, config_.port);
    cli.set_connection_timeout(1s);
    cli.set_read_timeout(2s);
    cli.set_write_timeout(2s);
    const auto started = Clock::now();
    auto backoff = Clock::duration(100ms);
    auto next_health = started;
    for (;;) {
        {
            std::lock_guard lock(mutex_);
            if (stopping_) return;
            if (shutdown_wanted_) break;
        }
        if (!ready_) {
            try_ready(cli, started);
            if (!ready_) {
                pause(backoff);
                backoff = std::min<Clock::duration>(backoff * 2, 2s);
            }
            continue;
        }
        if (Clock::now() >= next_health) {
            next_health = Clock::now() + seconds(config_.health_period_s);
            ping_health(cli);
        }
        pause(std::max<Clock::duration>(next_health - Clock::now(), 1ms));
    }
    send_shutdown(cli);
}

void AgonesClient::on_watch_line(const std::string& line) {
    const auto view = parse_gameserver(line);
    if (!view) {
        if (line.find_first_not_of(" \r\t") != std::string::npos) {
            spdlog::debug("agones: ignoring a watch line that is no GameServer ({} bytes)", line.size());
        }
        return;
    }
    last_contact_ = Clock::now().time_since_epoch().count();
    std::lock_guard lock(mutex_);
    if (!allocation_ && view->state == "Allocated") {
        allocation_ = *view;
        spdlog::info("agones: GameServer Allocated ({} annotations)", view->annotations.size());
    }
}

void AgonesClient::watch() {
    std::string buffer;
    bool logged = false;
    for (;;) {
        httplib::Client* cli = nullptr;
        {
            std::lock_guard lock(mutex_);
            if (stopping_) return;
            watch_client_ = std::make_unique<httplib::Client>(config_.host, config_.port);
            watch_client_->set_connection_timeout(1s);
            watch_client_->set_read_timeout(3600s);  // the stream is idle between changes
            cli = watch_client_.get();
        }
        buffer.clear();
        const httplib::Result res = cli->Get("/watch/gameserver", [&](const char* data, std::size_t n) {
            buffer.append(data, n);
            for (std::size_t nl; (nl = buffer.find('\n')) != std::string::npos; buffer.erase(0, nl + 1)) {
                on_watch_line(buffer.substr(0, nl));
            }
            return buffer.size() <= kMaxWatchLine;
        });
        if (!buffer.empty() && buffer.size() <= kMaxWatchLine) on_watch_line(buffer);
        if (!logged) {
            spdlog::debug("agones: watch ended ({}); reconnecting",
                          res ? "HTTP " + std::to_string(res->status) : httplib::to_string(res.error()));
            logged = true;
        }
        std::unique_lock lock(mutex_);
        if (wake_.wait_for(lock, 500ms, [this] { return stopping_; })) return;
    }
}

bool AgonesClient::shutdown(double wait_s) {
    {
        std::unique_lock lock(mutex_);
        shutdown_wanted_ = true;
        wake_.notify_all();
        if (worker_.joinable()) wake_.wait_for(lock, seconds(wait_s), [this] { return shutdown_done_; });
        stopping_ = true;
        if (watch_client_) watch_client_->stop();
    }
    wake_.notify_all();
    if (worker_.joinable()) worker_.join();
    if (watcher_.joinable()) watcher_.join();
    std::lock_guard lock(mutex_);
    return shutdown_ok_;
}

}  // namespace jetrace::ops
