// Captures what spdlog's default logger writes while it lives, so that tests
// can assert on the server's log.
#pragma once

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <memory>
#include <sstream>
#include <string>

namespace jetrace::test {

class LogCapture {
public:
    explicit LogCapture(spdlog::level::level_enum level = spdlog::level::info)
        : sink_(std::make_shared<spdlog::sinks::ostream_sink_mt>(text_)), old_level_(spdlog::get_level()) {
        sink_->set_pattern("[%l] %v");
        spdlog::default_logger()->sinks().push_back(sink_);
        spdlog::set_level(level);
    }
    ~LogCapture() {
        auto& sinks = spdlog::default_logger()->sinks();
        sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
        spdlog::set_level(old_level_);
    }
    LogCapture(const LogCapture&) = delete;
    LogCapture& operator=(const LogCapture&) = delete;

    std::string text() const { return text_.str(); }
    /// Whether one line contains every one of `parts` (in any order).
    template <typename... Parts>
    bool has_line(const Parts&... parts) const {
        std::istringstream in(text());
        for (std::string line; std::getline(in, line);) {
            if ((... && (line.find(parts) != std::string::npos))) return true;
        }
        return false;
    }

private:
    std::ostringstream text_;
    std::shared_ptr<spdlog::sinks::ostream_sink_mt> sink_;
    spdlog::level::level_enum old_level_;
};

}  // namespace jetrace::test
