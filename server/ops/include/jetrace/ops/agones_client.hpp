// An Agones SDK client over the sidecar's REST gateway (cpp-httplib), for
// jetrace-server. Every network call runs on its own threads, never on the
// caller's (the tick loop): the caller only flips flags and reads results.
//
// Lifecycle: start() sends Ready (retried with backoff until the sidecar
// answers or connect_timeout_s passes), then Health every health_period_s
// while the caller's heartbeat() is fresh (a stuck tick loop stops the
// pings, so Agones marks the GameServer Unhealthy), and watches the
// GameServer (GET /watch/gameserver) for its allocation. A sidecar that
// stops answering for connect_timeout_s is given up on: failure() says why.
#pragma once

#include "jetrace/ops/gameserver.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace httplib {
class Client;
}

namespace jetrace::ops {

struct AgonesConfig {
    std::string host = "localhost";
    int port = 9358;
    /// Between Health pings (unit: s).
    double health_period_s = 2.0;
    /// How long a sidecar that is not up yet, or stopped answering, is
    /// retried before failure() (unit: s).
    double connect_timeout_s = 30.0;
};

class AgonesClient {
public:
    explicit AgonesClient(AgonesConfig config);
    ~AgonesClient();
    AgonesClient(const AgonesClient&) = delete;
    AgonesClient& operator=(const AgonesClient&) = delete;

    /// Starts the worker (Ready, then Health) and the watch.
    void start();
    /// The caller's loop is alive (call it every iteration).
    void heartbeat();
    /// The GameServer as first seen Allocated, or nullopt until then.
    std::optional<GameServerView> allocation() const;
    /// True once the sidecar acknowledged Ready.
    bool ready() const { return ready_; }
    /// Non-empty once the sidecar is given up on.
    std::string failure() const;
    /// Sends Shutdown (retried until `wait_s` passes) and stops the threads.
    /// True if the sidecar acknowledged it.
    bool shutdown(double wait_s);

private:
    using Clock = std::chrono::steady_clock;
    void work();
    void try_ready(httplib::Client& cli, Clock::time_point started);
    void ping_health(httplib::Client& cli);
    void send_shutdown(httplib::Client& cli);
    void watch();
    bool post(httplib::Client& cli, const char* path, std::string& error);
    void on_watch_line(const std::string& line);
    void fail(const std::string& why);
    /// Sleeps up to `d` or until stop; false on stop.
    bool pause(Clock::duration d);

    AgonesConfig config_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::optional<GameServerView> allocation_;
    std::string failure_;
    bool stopping_ = false;
    bool shutdown_wanted_ = false;
    bool shutdown_done_ = false;
    bool shutdown_ok_ = false;
    std::atomic<bool> ready_{false};
    bool outage_logged_ = false;  // worker thread only
    std::atomic<Clock::rep> heartbeat_{0};
    std::atomic<Clock::rep> last_contact_{0};
    std::unique_ptr<httplib::Client> watch_client_;  // guarded by mutex_ (stop() from another thread)
    std::thread worker_, watcher_;
};

}  // namespace jetrace::ops
