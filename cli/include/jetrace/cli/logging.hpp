// The log of the command-line programs: a --log-level option, and spdlog's
// default logger on stderr, so that stdout carries only what scripts read
// (listening lines, results, JSON figures).
#pragma once

#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <string>

namespace jetrace::cli {

/// Adds --log-level (trace, debug, info, warn, error, off) to `app`; CLI11
/// rejects any other value.
inline void add_log_level_option(CLI::App& app, std::string& level) {
    app.add_option("--log-level", level, "trace, debug, info, warn, error, off")
        ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}));
}

/// Makes spdlog's default logger write to stderr at `level` (a value
/// add_log_level_option accepted), each line tagged with `name`.
inline void log_to_stderr(const std::string& name, const std::string& level) {
    spdlog::set_default_logger(spdlog::stderr_color_mt(name));
    spdlog::set_level(spdlog::level::from_str(level));
    spdlog::set_pattern("[%H:%M:%S.%e] [" + name + "] [%l] %v");
}

}  // namespace jetrace::cli
