// A Vec3 printed at full precision (17 significant digits), for test failure
// messages that must show every bit that differs.
#pragma once

#include "jetrace/core/math.hpp"

#include <sstream>
#include <string>

namespace jetrace::test {

inline std::string str(const Vec3& v) {
    std::ostringstream o;
    o.precision(17);
    o << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
    return o.str();
}

}  // namespace jetrace::test
