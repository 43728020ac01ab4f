// The fields of net::Conditions a user sets, with their names, units and
// ranges: one table for jetrace-netsim's options and jetrace-server's
// --web-link specification ("latency=50,loss=0.05").
#pragma once

#include "jetrace/net/scheduler.hpp"

#include <span>
#include <string>
#include <string_view>

namespace jetrace::net {

struct ConditionField {
    const char* name;
    const char* help;
    double lo;
    double hi;
    double Conditions::*field;
};

/// latency, jitter, loss, dup, reorder, rate, rate-burst, rate-queue, retransmit.
std::span<const ConditionField> condition_fields();

/// Sets the fields `spec` names ("NAME=VALUE,NAME=VALUE", names from
/// condition_fields()); false and `error` on an unknown name, a value that
/// is not a finite number in its field's range, or a name given twice.
bool parse_conditions(std::string_view spec, Conditions& out, std::string& error);

}  // namespace jetrace::net
