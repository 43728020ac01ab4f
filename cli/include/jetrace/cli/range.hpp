// A CLI11 check that a number option lies in a jetrace::ValueRange (the one
// the setting's validate() uses): NaN and infinity are refused too.
#pragma once

#include "jetrace/core/value_range.hpp"

#include <CLI/CLI.hpp>

#include <string>

namespace jetrace::cli {

inline CLI::Validator in_range(const ValueRange& r) {
    return CLI::Validator(
        [r](std::string& s) -> std::string {
            double v = 0;
            try {
                std::size_t used = 0;
                v = std::stod(s, &used);
            } catch (const std::out_of_range&) {
                return "Value " + s + " is out of the range of a double";
            } catch (const std::exception&) {
                return "";  // not a number at all: the option's own conversion says so
            }
            if (!std::isfinite(v)) return "Value " + s + " is not a finite number";
            if (!r.contains(v)) return "Value " + s + " not in range " + r.text();
            return "";
        },
        r.text());
}

}  // namespace jetrace::cli
