// ValueRange: the allowed values of one setting, written once and used both
// by validate() and by the command line (jetrace::cli::in_range), so the two
// cannot disagree. Non-finite values are never inside.
#pragma once

#include <cmath>
#include <string>

namespace jetrace {

struct ValueRange {
    double min = 0;
    double max = 0;
    /// Whether min / max themselves are excluded.
    bool min_open = false;
    bool max_open = false;

    bool contains(double v) const {
        if (!std::isfinite(v)) return false;
        if (min_open ? !(v > min) : !(v >= min)) return false;
        return max_open ? v < max : v <= max;
    }
    /// "[0, 600]", "(0, 3600]".
    std::string text() const {
        const auto num = [](double v) {
            std::string s = std::to_string(v);
            s.erase(s.find_last_not_of('0') + 1);
            if (!s.empty() && s.back() == '.') s.pop_back();
            return s;
        };
        return std::string(min_open ? "(" : "[") + num(min) + ", " + num(max) + (max_open ? ")" : "]");
    }
};

/// [min, max].
constexpr ValueRange closed(double min, double max) { return {min, max, false, false}; }
/// (min, max].
constexpr ValueRange above(double min, double max) { return {min, max, true, false}; }

}  // namespace jetrace
