// The track manifest's JSON (docs/TRACKS.md, "Track manifests"), read with
// nlohmann-json. Every key is checked for its type and range, and an unknown
// key is an error (a typo must not be ignored quietly).
#include "jetrace/tracks/track_manifest.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <functional>
#include <map>

namespace jetrace {
namespace {

using nlohmann::json;

bool fail(std::string& error, std::string message) {
    error = std::move(message);
    return false;
}

bool number(const json& v, const std::string& key, double lo, double hi, double& out, std::string& error) {
    if (!v.is_number()) return fail(error, "'" + key + "' must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x) || x < lo || x > hi) {
        return fail(error, "'" + key + "' is " + v.dump() + "; it must lie in [" + json(lo).dump() + ", " +
                               json(hi).dump() + "]");
    }
    out = x;
    return true;
}

bool strings(const json& v, const std::string& key, std::vector<std::string>& out, std::string& error) {
    if (v.is_string() && !v.get<std::string>().empty()) {
        out = {v.get<std::string>()};
        return true;
    }
    if (!v.is_array() || v.empty()) return fail(error, "'" + key + "' must be a string or a non-empty array of strings");
    out.clear();
    for (const json& s : v) {
        if (!s.is_string() || s.get<std::string>().empty()) return fail(error, "'" + key + "' holds a non-string or an empty string");
        out.push_back(s.get<std::string>());
    }
    return true;
}

bool point(const json& v, const std::string& key, RoutePoint& p, std::string& error) {
    if (!v.is_array() || (v.size() != 2 && v.size() != 3)) return fail(error, key + " must be [x, z] or [x, y, z]");
    double c[3] = {0, 0, 0};
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (!number(v[i], key, -kMaxTrackCoordinate_m, kMaxTrackCoordinate_m, c[i], error)) return false;
    }
    p.x = c[0];
    p.z = v.size() == 2 ? c[1] : c[2];
    if (v.size() == 3) p.y = c[1];
    return true;
}

bool route(const json& v, TrackManifest& m, std::string& error) {
    if (!v.is_array() || v.size() < 3 || v.size() > 100000) return fail(error, "'route' must hold 3 to 100000 points");
    m.route.resize(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (!point(v[i], "route point " + std::to_string(i), m.route[i], error)) return false;
    }
    return true;
}

bool gate(const json& v, std::size_t i, ManifestGate& g, std::string& error) {
    const std::string what = "gate " + std::to_string(i);
    if (!v.is_object()) return fail(error, what + " must be an object");
    for (const auto& [key, val] : v.items()) {
        if (key == "position") {
            if (!point(val, what + " 'position'", g.position, error)) return false;
        } else if (key == "direction") {
            RoutePoint d;
            if (!point(val, what + " 'direction'", d, error)) return false;
            const Vec3 dir(d.x, 0.0, d.z);
            if (!(dir.norm() > 1e-9)) return fail(error, what + " 'direction' has no horizontal part");
            g.direction = dir.normalized();
        } else if (key == "width_m") {
            if (!number(val, what + " 'width_m'", 0.5, 1e4, g.width_m, error)) return false;
        } else if (key == "height_m") {
            if (!number(val, what + " 'height_m'", 0.5, 1e4, g.height_m, error)) return false;
        } else {
            return fail(error, what + ": unknown key '" + key + "' (position, direction, width_m, height_m)");
        }
    }
    if (!v.contains("position")) return fail(error, what + " needs a 'position'");
    return true;
}

bool gates(const json& v, TrackManifest& m, std::string& error) {
    if (!v.is_array() || v.size() < 2 || v.size() > 10000) return fail(error, "'gates' must hold 2 to 10000 gates");
    m.gates.resize(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (!gate(v[i], i, m.gates[i], error)) return false;
    }
    return true;
}

bool choice(const json& v, const std::string& key, std::string_view a, std::string_view b, bool& is_b,
            std::string& error) {
    if (!v.is_string() || (v.get<std::string>() != a && v.get<std::string>() != b)) {
        return fail(error, "'" + key + "' must be \"" + std::string(a) + "\" or \"" + std::string(b) + "\"");
    }
    is_b = v.get<std::string>() == b;
    return true;
}

using Reader = std::function<bool(const json&, TrackManifest&, std::string&)>;

Reader num(double lo, double hi, double TrackManifest::*field, const char* key) {
    return [=](const json& v, TrackManifest& m, std::string& e) { return number(v, key, lo, hi, m.*field, e); };
}

const std::map<std::string, Reader, std::less<>>& readers() {
    static const std::map<std::string, Reader, std::less<>> r = {
        {"name", [](const json& v, TrackManifest& m, std::string& e) {
             if (!v.is_string() || v.get<std::string>().empty()) return fail(e, "'name' must be a non-empty string");
             m.name = v.get<std::string>();
             return true;
         }},
        {"mesh", [](const json& v, TrackManifest& m, std::string& e) { return strings(v, "mesh", m.meshes, e); }},
        {"meshes", [](const json& v, TrackManifest& m, std::string& e) { return strings(v, "meshes", m.meshes, e); }},
        {"scale", num(1e-4, 1e4, &TrackManifest::scale, "scale")},
        {"up", [](const json& v, TrackManifest& m, std::string& e) {
             bool z = false;
             if (!choice(v, "up", "y", "z", z, e)) return false;
             m.up = z ? 'z' : 'y';
             return true;
         }},
        {"drivable", [](const json& v, TrackManifest& m, std::string& e) { return strings(v, "drivable", m.drivable, e); }},
        {"ignore", [](const json& v, TrackManifest& m, std::string& e) { return strings(v, "ignore", m.ignore, e); }},
        {"route", route},
        {"route_surface", [](const json& v, TrackManifest& m, std::string& e) {
             bool high = false;
             if (!choice(v, "route_surface", "lowest", "highest", high, e)) return false;
             m.route_surface = high ? RouteSurface::highest : RouteSurface::lowest;
             return true;
         }},
        {"gate_spacing_m", num(5, 1e4, &TrackManifest::gate_spacing_m, "gate_spacing_m")},
        {"gate_width_m", num(1, 1e4, &TrackManifest::gate_width_m, "gate_width_m")},
        {"gate_height_m", num(1, 1e4, &TrackManifest::gate_height_m, "gate_height_m")},
        {"gates", gates},
        {"spawn_count", [](const json& v, TrackManifest& m, std::string& e) {
             double n = 0;
             if (!number(v, "spawn_count", 1, 64, n, e)) return false;
             if (n != std::floor(n)) return fail(e, "'spawn_count' must be a whole number");
             m.spawn_count = static_cast<int>(n);
             return true;
         }},
        {"spawn_row_spacing_m", num(5, 1000, &TrackManifest::spawn_row_spacing_m, "spawn_row_spacing_m")},
        {"spawn_column_spacing_m", num(0, 100, &TrackManifest::spawn_column_spacing_m, "spawn_column_spacing_m")},
        {"spawn_back_m", num(0, 1000, &TrackManifest::spawn_back_m, "spawn_back_m")},
        {"kill_height_m", [](const json& v, TrackManifest& m, std::string& e) {
             double k = 0;
             if (!number(v, "kill_height_m", -kMaxTrackCoordinate_m, kMaxTrackCoordinate_m, k, e)) return false;
             m.kill_height_m = k;
             return true;
         }},
    };
    return r;
}

std::string key_list() {
    std::string s;
    for (const auto& entry : readers()) s += (s.empty() ? "" : ", ") + entry.first;
    return s;
}

}  // namespace

bool parse_manifest(std::string_view text, const std::string& dir, TrackManifest& out, std::string& error) {
    if (text.size() > kMaxManifestBytes) return fail(error, "the manifest is larger than 16 MiB");
    const json doc = json::parse(text.begin(), text.end(), nullptr, false);
    if (doc.is_discarded()) return fail(error, "the manifest is not valid JSON");
    if (!doc.is_object()) return fail(error, "the manifest must be a JSON object");
    TrackManifest m;
    for (const auto& [key, value] : doc.items()) {
        const auto it = readers().find(key);
        if (it == readers().end()) return fail(error, "unknown key '" + key + "' (known: " + key_list() + ")");
        if (!it->second(value, m, error)) return false;
    }
    if (doc.contains("mesh") && doc.contains("meshes")) return fail(error, "give 'mesh' or 'meshes', not both");
    if (m.meshes.empty()) return fail(error, "the manifest names no mesh ('mesh' or 'meshes')");
    if (m.route.empty() && m.gates.empty()) return fail(error, "the manifest needs a 'route' or 'gates'");
    if (m.route.empty()) {
        for (std::size_t i = 0; i < m.gates.size(); ++i) {
            if (!m.gates[i].direction) return fail(error, "gate " + std::to_string(i) + " needs a 'direction' (there is no route)");
        }
    }
    for (std::string& mesh : m.meshes) {
        if (std::filesystem::path(mesh).is_relative()) mesh = (std::filesystem::path(dir) / mesh).lexically_normal().string();
    }
    out = std::move(m);
    return true;
}

}  // namespace jetrace
