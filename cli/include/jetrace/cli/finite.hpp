// A CLI11 check that a number option is finite: CLI::Range lets NaN through
// (every comparison with it is false) and "inf" parses as a double.
#pragma once

#include <CLI/CLI.hpp>

#include <cmath>
#include <string>

namespace jetrace::cli {

inline CLI::Validator finite() {
    return CLI::Validator(
        [](std::string& s) -> std::string {
            try {
                if (std::isfinite(std::stod(s))) return "";
            } catch (const std::out_of_range&) {
                return "Value " + s + " is not a finite number";  // beyond a double, or below its smallest
            } catch (const std::exception&) {
                return "";  // not a number at all: the option's own conversion says so
            }
            return "Value " + s + " is not a finite number";
        },
        "FINITE");
}

}  // namespace jetrace::cli
