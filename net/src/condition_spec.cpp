// condition_fields() and parse_conditions() (condition_spec.hpp).
#include "jetrace/net/condition_spec.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <set>
#include <sstream>

namespace jetrace::net {
namespace {

constexpr std::array kFields = {
    ConditionField{"latency", "added one-way delay (ms)", 0, 10000, &Conditions::latency_ms},
    ConditionField{"jitter", "extra delay, uniform in [0, MS] (ms)", 0, 10000, &Conditions::jitter_ms},
    ConditionField{"loss", "probability a datagram is dropped", 0, 1, &Conditions::loss},
    ConditionField{"dup", "probability a datagram is duplicated", 0, 1, &Conditions::duplicate},
    ConditionField{"reorder", "probability a datagram is held behind the next", 0, 1, &Conditions::reorder},
    ConditionField{"rate", "bandwidth per client (kbit/s of payload; 0: unlimited)", 0, 1e7, &Conditions::rate_kbps},
    ConditionField{"rate-burst", "token bucket size (bytes)", 1, 1e7, &Conditions::burst_bytes},
    ConditionField{"rate-queue", "longest wait for the link before a datagram is dropped (ms)", 0, 10000,
                   &Conditions::rate_queue_ms},
    ConditionField{"retransmit", "a lost reliable datagram (every message of a stream) is resent this much later, "
                                 "doubling with each loss (ms; 0: reliable ones are never lost)",
                   0, 60000, &Conditions::retransmit_ms},
};

}  // namespace

std::span<const ConditionField> condition_fields() { return kFields; }

bool parse_conditions(std::string_view spec, Conditions& out, std::string& error) {
    std::set<std::string_view> seen;
    Conditions c = out;
    while (!spec.empty()) {
        const std::size_t comma = spec.find(',');
        const std::string_view item = spec.substr(0, comma);
        spec = comma == std::string_view::npos ? std::string_view{} : spec.substr(comma + 1);
        const std::size_t eq = item.find('=');
        if (eq == std::string_view::npos) {
            std::ostringstream why;
            why << "'" << item << "' is not NAME=VALUE";
            error = why.str();
            return false;
        }
        const std::string_view name = item.substr(0, eq);
        const std::string_view text = item.substr(eq + 1);
        const ConditionField* field = nullptr;
        for (const ConditionField& f : kFields) {
            if (name == f.name) field = &f;
        }
        if (!field) {
            std::ostringstream why;
            why << "unknown condition '" << name << "' (";
            for (const ConditionField& f : kFields) why << (&f == kFields.data() ? "" : ", ") << f.name;
            why << ")";
            error = why.str();
            return false;
        }
        if (!seen.insert(name).second) {
            std::ostringstream why;
            why << "'" << name << "' given twice";
            error = why.str();
            return false;
        }
        double v = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (ec != std::errc{} || end != text.data() + text.size() || !std::isfinite(v) || v < field->lo ||
            v > field->hi) {
            std::ostringstream why;
            why << name << " must be a number in [" << field->lo << ", " << field->hi << "] (" << field->help
                << "), got '" << text << "'";
            error = why.str();
            return false;
        }
        c.*(field->field) = v;
    }
    out = c;
    return true;
}

}  // namespace jetrace::net
