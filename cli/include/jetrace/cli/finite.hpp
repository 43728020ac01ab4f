// CLI11's Range lets NaN through (every comparison with NaN is false):
// options that take a real number check `finite()` too, so NaN and
// infinities get a message and a non-zero exit like any value out of range.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>

namespace jetrace::cli {

/// A validator that refuses NaN and +-infinity (and anything not a number).
inline CLI::Validator finite() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            double v = 0;
            if (!CLI::detail::lexical_cast(text, v)) return "not a number: " + text;
            return std::isfinite(v) ? std::string() : "not a finite number: " + text;
        },
        "FINITE");
}

}  // namespace jetrace::cli
