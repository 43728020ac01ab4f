#include "jetrace/client/drawn_check.hpp"

#include <bit>

namespace jetrace::client {

const char* to_string(DrawnCause c) {
    switch (c) {
        case DrawnCause::late_input: return "late_input";
        case DrawnCause::near_car: return "near_car";
        case DrawnCause::none: break;
    }
    return "none";
}

bool DrawnCheck::confirm(std::uint32_t tick, const Vec3& server, DrawnCause cause) {
    Drawn* d = drawn_.find(tick);
    if (d == nullptr || d->compared) return false;
    d->compared = true;
    last_.tick = tick;
    last_.drawn = d->p;
    last_.same = true;
    for (int i = 0; i < 3; ++i) {
        last_.same = last_.same && std::bit_cast<std::uint64_t>(d->p[i]) == std::bit_cast<std::uint64_t>(server[i]);
    }
    last_.smoothing = d->smoothing;
    if (cause == DrawnCause::none && d->smoothing) cause = d->offset_cause;
    last_.cause = last_.same ? DrawnCause::none : cause;
    return true;
}

}  // namespace jetrace::client
