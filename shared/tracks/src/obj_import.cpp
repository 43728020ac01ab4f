// Wavefront OBJ import and export of tracks. The convention (which group
// names mean what, how gates and spawns are derived) is in docs/TRACKS.md.
//
// tinyobjloader parses the structure: groups, faces and their triangulation.
// A light pre-pass over the lines does three things tinyobjloader cannot:
//  * reads `v` coordinates with std::from_chars. tinyobjloader silently turns
//    a number it cannot read ("nan", "1.5e") into 0, and its decimal reader
//    is not correctly rounded (it also calls libm's pow), so two machines
//    could disagree on a coordinate and hence on the track identity.
//    from_chars is exact and portable; both readings are cross-checked.
//  * checks every face index before tinyobjloader sees it (tinyobjloader
//    only warns about out-of-range indices and keeps them);
//  * remembers line numbers of groups for error messages.
#include "jetrace/tracks/track_io.hpp"
#include "track_raycast.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

static_assert(sizeof(tinyobj::real_t) == sizeof(double),
              "link tinyobjloader::tinyobjloader_double (it defines TINYOBJLOADER_USE_DOUBLE)");

namespace jetrace {
namespace {

using detail::kRest_m;
using detail::Rest;
using detail::rest_on_surface;

// Memory guards of the pre-pass, before tinyobjloader parses anything: the
// track's limit plus room for gate and spawn markers.
constexpr std::size_t kMaxFileTriangles = kMaxTrackTriangles + 100'000;
constexpr std::size_t kMaxFileVertices = 3 * kMaxTrackTriangles;
constexpr std::string_view kGroupHelp = "expected 'track...', 'checkpoint_N', 'spawn_N' or 'kill_height'";

std::string at_line(std::size_t line) { return "line " + std::to_string(line) + ": "; }
std::string quoted(std::string_view s) { return "'" + std::string(s) + "'"; }
bool fail(std::string& error, std::string message) {
    error = std::move(message);
    return false;
}

std::string_view trim(std::string_view s) {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string_view::npos) return {};
    return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

std::vector<std::string_view> split_ws(std::string_view s) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (true) {
        i = s.find_first_not_of(" \t", i);
        if (i == std::string_view::npos) return out;
        const std::size_t e = std::min(s.find_first_of(" \t", i), s.size());
        out.push_back(s.substr(i, e - i));
        i = e;
    }
}

// ---------------------------------------------------------------- pre-pass

struct Scan {
    std::vector<Vec3> vertices;           // exact, in file order
    std::vector<std::size_t> vertex_line;  // line of each vertex
    /// Line of the `g`/`o` statement that first gave faces to each group name;
    /// for "" (faces outside any group) the line of the first such face.
    std::map<std::string, std::size_t, std::less<>> group_line;
    std::string group;       // current group name
    std::size_t group_stmt = 0;  // line of the current g/o statement (0: none)
    bool group_recorded = false;
    std::size_t triangles = 0;
    std::size_t max_ref = 0, max_ref_line = 0;  // largest positive vertex index
};

bool parse_real(std::string_view tok, double& out) {
    if (tok.size() > 1 && tok[0] == '+' && tok[1] != '-' && tok[1] != '+') tok.remove_prefix(1);
    const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
    return r.ec == std::errc() && r.ptr == tok.data() + tok.size();
}

bool scan_vertex(std::string_view rest, std::size_t line, Scan& s, std::string& error) {
    std::vector<double> values;
    for (std::string_view tok : split_ws(rest)) {
        if (tok[0] == '#') break;  // trailing comment
        double x = 0;
        if (!parse_real(tok, x)) return fail(error, at_line(line) + quoted(tok) + " is not a number (or out of range)");
        if (!std::isfinite(x)) return fail(error, at_line(line) + "vertex value " + quoted(tok) + " is not finite");
        values.push_back(x);
    }
    if (values.size() < 3 || values.size() > 7) {
        return fail(error, at_line(line) + "a vertex needs x y z (optionally w or r g b), found " +
                               std::to_string(values.size()) + " numbers");
    }
    for (int i = 0; i < 3; ++i) {
        if (std::abs(values[i]) > kMaxTrackCoordinate_m) return fail(error, at_line(line) + "coordinate exceeds 1e6 m");
    }
    if (s.vertices.size() >= kMaxFileVertices) {
        return fail(error, at_line(line) + "too many vertices (more than " + std::to_string(kMaxFileVertices) + ")");
    }
    s.vertices.emplace_back(values[0], values[1], values[2]);
    s.vertex_line.push_back(line);
    return true;
}

// One `f` reference: "i", "i/j", "i//k" or "i/j/k"; only i matters here.
bool scan_face_ref(std::string_view tok, std::size_t line, Scan& s, std::string& error) {
    std::string_view num = tok.substr(0, tok.find('/'));
    if (num.size() > 1 && num[0] == '+' && num[1] != '-') num.remove_prefix(1);
    int idx = 0;
    const auto r = std::from_chars(num.data(), num.data() + num.size(), idx);
    if (r.ec == std::errc::result_out_of_range) {
        return fail(error, at_line(line) + "face index " + quoted(num) + " is out of range");
    }
    if (r.ec != std::errc() || r.ptr != num.data() + num.size() || num.empty()) {
        return fail(error, at_line(line) + "bad face vertex " + quoted(tok));
    }
    if (idx == 0) return fail(error, at_line(line) + "face index 0 is invalid (OBJ indices start at 1)");
    if (idx < 0) {  // relative to the vertices read so far
        if (static_cast<std::size_t>(-static_cast<long long>(idx)) > s.vertices.size()) {
            return fail(error, at_line(line) + "face index " + std::to_string(idx) + " is out of range (only " +
                                   std::to_string(s.vertices.size()) + " vertices before this line)");
        }
    } else if (static_cast<std::size_t>(idx) > s.max_ref) {
        s.max_ref = static_cast<std::size_t>(idx);
        s.max_ref_line = line;
    }
    return true;
}

bool scan_face(std::string_view rest, std::size_t line, Scan& s, std::string& error) {
    const std::vector<std::string_view> refs = split_ws(rest);
    if (refs.size() < 3) return fail(error, at_line(line) + "a face needs at least 3 vertices");
    for (std::string_view tok : refs) {
        if (!scan_face_ref(tok, line, s, error)) return false;
    }
    s.triangles += refs.size() - 2;
    if (s.triangles > kMaxFileTriangles) {
        return fail(error, at_line(line) + "too many faces (over " + std::to_string(kMaxFileTriangles) + " triangles)");
    }
    if (!s.group_recorded) {
        s.group_line.try_emplace(s.group, s.group.empty() ? line : s.group_stmt);
        s.group_recorded = true;
    }
    return true;
}

// The group name as tinyobjloader reports it, trimmed.
std::string group_name(char keyword, std::string_view rest) {
    if (keyword == 'o') return std::string(trim(rest));
    std::string name;
    for (std::string_view n : split_ws(rest)) {
        if (!name.empty()) name.push_back(' ');
        name.append(n);
    }
    return name;
}

// Mirrors tinyobjloader's line splitting (\n, \r\n, \r) and line keywords.
bool scan_text(std::string_view text, Scan& s, std::string& error) {
    std::size_t pos = 0, line = 0;
    while (pos < text.size()) {
        const std::size_t end = std::min(text.find_first_of("\r\n", pos), text.size());
        const std::string_view raw = text.substr(pos, end - pos);
        pos = end;
        if (pos < text.size()) pos += (text[pos] == '\r' && pos + 1 < text.size() && text[pos + 1] == '\n') ? 2 : 1;
        ++line;
        if (raw.find('\0') != std::string_view::npos) {
            return fail(error, at_line(line) + "contains a NUL byte (not a text OBJ file?)");
        }
        std::string_view t = raw.substr(std::min(raw.find_first_not_of(" \t"), raw.size()));
        if (t.size() < 2 || (t[1] != ' ' && t[1] != '\t')) continue;
        const std::string_view rest = t.substr(2);
        bool ok = true;
        switch (t[0]) {
            case 'v': ok = scan_vertex(rest, line, s, error); break;
            case 'f': ok = scan_face(rest, line, s, error); break;
            case 'g':  // tinyobjloader joins several names with one space
            case 'o':  // tinyobjloader keeps the rest of the line
                s.group = group_name(t[0], rest);
                s.group_stmt = line;
                s.group_recorded = false;
                break;
            default: break;
        }
        if (!ok) return false;
    }
    if (s.max_ref <= s.vertices.size()) return true;
    return fail(error, at_line(s.max_ref_line) + "face index " + std::to_string(s.max_ref) +
                           " is out of range (the file has " + std::to_string(s.vertices.size()) + " vertices)");
}

// ------------------------------------------------------- group collection

struct Group {
    std::string name;
    std::size_t line = 0;
    std::vector<std::uint32_t> idx;  // triangles, 3 per face
};

struct Parts {
    std::vector<std::uint32_t> track;
    std::map<long, Group> gates, spawns;
    std::vector<std::uint32_t> kill;
};

// Faces of each (trimmed) group name, in file order.
bool collect_groups(const tinyobj::ObjReader& reader, std::size_t nverts, std::map<std::string, Group>& groups,
                    std::string& error) {
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const std::string name(trim(shape.name));
        Group& g = groups[name];
        g.name = name;
        for (unsigned char n : shape.mesh.num_face_vertices) {
            if (n != 3) return fail(error, "group " + quoted(name) + ": the OBJ parser returned a non-triangle");
        }
        for (const tinyobj::index_t& i : shape.mesh.indices) {
            if (i.vertex_index < 0 || static_cast<std::size_t>(i.vertex_index) >= nverts) {
                return fail(error, "group " + quoted(name) + ": face index " + std::to_string(i.vertex_index + 1) +
                                       " is out of range");
            }
            g.idx.push_back(static_cast<std::uint32_t>(i.vertex_index));
        }
    }
    return true;
}

// "checkpoint_07" with prefix "checkpoint_": 1 and n = 7; 0 if the prefix
// does not match; -1 if it matches but no number follows.
int numbered(const std::string& name, std::string_view prefix, long& n) {
    if (!name.starts_with(prefix)) return 0;
    const std::string_view digits = std::string_view(name).substr(prefix.size());
    if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != digits.npos) return -1;
    std::from_chars(digits.data(), digits.data() + digits.size(), n);
    return 1;
}

bool add_numbered(std::map<long, Group>& into, long n, Group&& g, const char* what, std::string& error) {
    const auto [it, inserted] = into.try_emplace(n, std::move(g));  // g is left alone if n exists
    if (inserted) return true;
    return fail(error, std::string("duplicate ") + what + " " + std::to_string(n) + ": groups " +
                           quoted(it->second.name) + " (line " + std::to_string(it->second.line) + ") and " +
                           quoted(g.name) + " (line " + std::to_string(g.line) + ")");
}

bool classify(std::map<std::string, Group>& groups, const Scan& s, Parts& p, std::string& error) {
    for (auto& [name, g] : groups) {
        if (g.idx.empty()) continue;  // groups without faces are ignored
        const auto line_it = s.group_line.find(name);
        g.line = line_it == s.group_line.end() ? 0 : line_it->second;
        const std::string where = g.line ? at_line(g.line) : std::string();
        long n = 0;
        if (name.empty()) return fail(error, where + "faces outside any group (" + std::string(kGroupHelp) + ")");
        if (name.find_first_of(" \t") != std::string::npos) {
            return fail(error, where + "group name " + quoted(name) + " has several words; use exactly one (" +
                                   std::string(kGroupHelp) + ")");
        }
        if (name.starts_with("track")) {
            p.track.insert(p.track.end(), g.idx.begin(), g.idx.end());
        } else if (name == "kill_height") {
            p.kill = g.idx;
        } else if (const int c = numbered(name, "checkpoint_", n); c != 0) {
            if (c < 0) return fail(error, where + "group " + quoted(name) + ": expected checkpoint_<number>");
            if (!add_numbered(p.gates, n, std::move(g), "checkpoint", error)) return false;
        } else if (const int sp = numbered(name, "spawn_", n); sp != 0) {
            if (sp < 0) return fail(error, where + "group " + quoted(name) + ": expected spawn_<number>");
            if (!add_numbered(p.spawns, n, std::move(g), "spawn", error)) return false;
        } else {
            return fail(error, where + "unknown group " + quoted(name) + " (" + std::string(kGroupHelp) + ")");
        }
    }
    return true;
}

bool check_numbering(const std::map<long, Group>& m, const char* what, std::string& error) {
    long expected = 0;
    for (const auto& entry : m) {
        if (entry.first != expected) {
            return fail(error, std::string(what) + " " + std::to_string(expected) + " is missing (" + what +
                                   "s must be numbered 0..K-1 without gaps)");
        }
        ++expected;
    }
    return true;
}

bool check_parts(const Parts& p, std::string& error) {
    if (p.track.empty()) {
        return fail(error, "no 'track' group: the drivable mesh must be under 'g track' (or a name starting 'track')");
    }
    if (p.track.size() / 3 > kMaxTrackTriangles) {
        return fail(error, "the track has " + std::to_string(p.track.size() / 3) + " triangles; at most " +
                               std::to_string(kMaxTrackTriangles) + " are allowed");
    }
    if (p.gates.size() < 2) {
        return fail(error, "the track needs at least 2 checkpoints (checkpoint_0 is the start/finish line), found " +
                               std::to_string(p.gates.size()));
    }
    if (p.spawns.empty()) return fail(error, "no spawn: add at least one 'spawn_0' triangle");
    return check_numbering(p.gates, "checkpoint", error) && check_numbering(p.spawns, "spawn", error);
}

// ------------------------------------------------------------- geometry

// Distinct positions (bitwise) in order of first use.
std::vector<Vec3> distinct_points(const std::vector<Vec3>& verts, const std::vector<std::uint32_t>& idx) {
    std::vector<Vec3> out;
    for (std::uint32_t i : idx) {
        if (std::find(out.begin(), out.end(), verts[i]) == out.end()) out.push_back(verts[i]);
    }
    return out;
}

Vec3 mean(const std::vector<Vec3>& pts) {
    Vec3 sum = Vec3::Zero();
    for (const Vec3& p : pts) sum += p;
    return sum / static_cast<double>(pts.size());
}

bool fit_gate(long number, const std::vector<Vec3>& verts, const Group& g, const std::vector<Triangle>& tris,
              Checkpoint& c, std::string& error) {
    const std::string what = "checkpoint " + std::to_string(number) + " (group '" + g.name + "'): ";
    const std::vector<Vec3> pts = g.idx.size() == 6 ? distinct_points(verts, g.idx) : std::vector<Vec3>{};
    if (pts.size() != 4) return fail(error, what + "needs exactly one quad (or two triangles over 4 vertices)");
    const Triangle t0 = Triangle::make(verts[g.idx[0]], verts[g.idx[1]], verts[g.idx[2]]);
    const Triangle t1 = Triangle::make(verts[g.idx[3]], verts[g.idx[4]], verts[g.idx[5]]);
    if (t0.degenerate || t1.degenerate || !(t0.normal().dot(t1.normal()) > 0.0)) {
        return fail(error, what + "its quad has no area or its two triangles face opposite ways");
    }
    const Vec3 n1 = (t0.b - t0.a).cross(t0.c - t0.a), n2 = (t1.b - t1.a).cross(t1.c - t1.a);
    c.normal = (n1 + n2).normalized();
    const Vec3 up = kWorldUp - c.normal * c.normal.y();
    if (!(up.norm() > 0.01)) {
        return fail(error, what + "the gate is horizontal (its normal points along world Y); gates must stand upright");
    }
    c.up = up.normalized();
    c.across = c.normal.cross(c.up);
    c.center = mean(pts);
    c.half_width_m = 0;
    c.half_height_m = 0;
    for (const Vec3& p : pts) {
        c.half_width_m = std::max(c.half_width_m, std::abs((p - c.center).dot(c.across)));
        c.half_height_m = std::max(c.half_height_m, std::abs((p - c.center).dot(c.up)));
    }
    if (!(c.half_width_m > 0.0 && c.half_height_m > 0.0)) return fail(error, what + "zero width or height");
    switch (rest_on_surface(tris, c.center, -c.up, c.normal, c.respawn)) {
        case Rest::ok: return true;
        case Rest::no_surface:
            return fail(error, "checkpoint " + std::to_string(number) + " has no track surface below its centre");
        case Rest::bad_forward: break;
    }
    return fail(error, what + "the surface below the gate is perpendicular to the direction of travel");
}

bool make_spawn(long number, const std::vector<Vec3>& verts, const Group& g, const std::vector<Triangle>& tris,
                Pose& pose, std::string& error) {
    const std::string what = "spawn " + std::to_string(number) + " (group '" + g.name + "'): ";
    const std::vector<Vec3> pts =
        (g.idx.size() == 3 || g.idx.size() == 6) ? distinct_points(verts, g.idx) : std::vector<Vec3>{};
    if (pts.size() < 3 || pts.size() > 4) return fail(error, what + "needs exactly one triangle (or quad)");
    const Vec3 centroid = mean(pts);
    switch (rest_on_surface(tris, centroid + kWorldUp * kRest_m, -kWorldUp, verts[g.idx[0]] - centroid, pose)) {
        case Rest::ok: return true;
        case Rest::no_surface:
            return fail(error, "spawn " + std::to_string(number) + " has no track surface below its centroid");
        case Rest::bad_forward: break;
    }
    return fail(error, what + "its first vertex must point from the centroid along the surface (driving direction)");
}

bool parse_obj(std::string_view text, Scan& scan, std::map<std::string, Group>& groups, std::string& error) {
    if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
        return fail(error, "empty OBJ text (no vertices or faces)");
    }
    if (!scan_text(text, scan, error)) return false;
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromString(std::string(text), std::string(), config)) {
        error = "OBJ parser: " + std::string(trim(reader.Error()));
        if (!trim(reader.Warning()).empty()) error += " (warnings: " + std::string(trim(reader.Warning())) + ")";
        return false;
    }
    const std::vector<tinyobj::real_t>& v = reader.GetAttrib().vertices;
    if (v.size() != 3 * scan.vertices.size()) {
        return fail(error, "OBJ parser read " + std::to_string(v.size() / 3) + " vertices where " +
                               std::to_string(scan.vertices.size()) + " 'v' lines were found");
    }
    for (std::size_t i = 0; i < scan.vertices.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const double exact = scan.vertices[i][k], theirs = static_cast<double>(v[3 * i + k]);
            if (!(std::abs(exact - theirs) <= 1e-9 * std::max(1.0, std::abs(exact)))) {
                return fail(error, at_line(scan.vertex_line[i]) + "coordinate read inconsistently by the OBJ parser");
            }
        }
    }
    return collect_groups(reader, scan.vertices.size(), groups, error);
}

// -------------------------------------------------------------- export

void put(std::string& out, double x) {
    char buf[40];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);  // shortest exact round trip
    out.append(buf, r.ptr);
}

void put_vertex(std::string& out, const Vec3& p) {
    out += 'v';
    for (int i = 0; i < 3; ++i) {
        out += ' ';
        put(out, p[i]);
    }
    out += '\n';
}

// Writes `g name`, the points and one face over them; returns the new count.
std::size_t put_face_group(std::string& out, const std::string& name, const std::vector<Vec3>& pts,
                           std::size_t count) {
    out += "g " + name + '\n';
    for (const Vec3& p : pts) put_vertex(out, p);
    out += 'f';
    for (std::size_t i = 0; i < pts.size(); ++i) out += ' ' + std::to_string(count + i + 1);
    out += '\n';
    return count + pts.size();
}

}  // namespace

bool import_obj(std::string_view text, const std::string& name, Track& out, std::string& error) {
    Scan scan;
    std::map<std::string, Group> groups;
    Parts parts;
    if (!parse_obj(text, scan, groups, error) || !classify(groups, scan, parts, error) || !check_parts(parts, error)) {
        return false;
    }
    Track track = make_track(name, scan.vertices, parts.track, {}, {}, 0.0);
    for (const auto& [n, g] : parts.gates) {
        if (!fit_gate(n, scan.vertices, g, track.triangles, track.checkpoints.emplace_back(), error)) return false;
    }
    for (const auto& [n, g] : parts.spawns) {
        if (!make_spawn(n, scan.vertices, g, track.triangles, track.spawns.emplace_back(), error)) return false;
    }
    track.kill_height_m = track.bounds.min.y() - 50.0;
    if (!parts.kill.empty()) {
        track.kill_height_m = scan.vertices[parts.kill[0]].y();
        for (std::uint32_t i : parts.kill) track.kill_height_m = std::min(track.kill_height_m, scan.vertices[i].y());
    }
    if (std::string problem = validate(track); !problem.empty()) return fail(error, std::move(problem));
    out = std::move(track);
    return true;
}

bool import_obj_mesh(std::string_view text, ImportedMesh& out, std::string& error) {
    Scan scan;
    std::map<std::string, Group> groups;
    if (!parse_obj(text, scan, groups, error)) return false;
    ImportedMesh mesh;
    for (const auto& [name, g] : groups) {
        if (g.idx.empty()) continue;
        MeshPart& part = mesh.parts.emplace_back();
        part.name = name;
        for (std::uint32_t i : g.idx) part.corners.push_back(scan.vertices[i]);
    }
    if (mesh.parts.empty()) return fail(error, "the OBJ file has no faces");
    out = std::move(mesh);
    return true;
}

std::string export_obj(const Track& track) {
    std::string out = "# jetrace track '" + track.name + "' (convention: docs/TRACKS.md)\n";
    out += "# " + std::to_string(track.triangles.size()) + " triangles, " +
           std::to_string(track.checkpoints.size()) + " checkpoints, " + std::to_string(track.spawns.size()) +
           " spawns\n";
    // Track mesh: vertices shared bitwise, triangles in order.
    std::map<std::array<std::uint64_t, 3>, std::size_t> index_of;
    std::vector<Vec3> verts;
    std::vector<std::size_t> faces;
    for (const Triangle& t : track.triangles) {
        for (const Vec3* p : {&t.a, &t.b, &t.c}) {
            const std::array<std::uint64_t, 3> key{std::bit_cast<std::uint64_t>(p->x()),
                                                   std::bit_cast<std::uint64_t>(p->y()),
                                                   std::bit_cast<std::uint64_t>(p->z())};
            const auto [it, added] = index_of.try_emplace(key, verts.size());
            if (added) verts.push_back(*p);
            faces.push_back(it->second + 1);
        }
    }
    out += "g track\n";
    for (const Vec3& p : verts) put_vertex(out, p);
    for (std::size_t i = 0; i + 2 < faces.size(); i += 3) {
        out += "f " + std::to_string(faces[i]) + ' ' + std::to_string(faces[i + 1]) + ' ' +
               std::to_string(faces[i + 2]) + '\n';
    }
    std::size_t count = verts.size();
    for (std::size_t i = 0; i < track.checkpoints.size(); ++i) {
        const Checkpoint& c = track.checkpoints[i];
        // Unit directions: a frame that is only nearly unit would stretch the quad.
        const Vec3 a = c.normal.cross(c.up).normalized() * c.half_width_m, u = c.up.normalized() * c.half_height_m;
        // Wound so that the right-hand-rule normal is the direction of travel.
        count = put_face_group(out, "checkpoint_" + std::to_string(i),
                               {c.center - a - u, c.center - a + u, c.center + a + u, c.center + a - u}, count);
    }
    for (std::size_t i = 0; i < track.spawns.size(); ++i) {
        const Pose& p = track.spawns[i];
        const Vec3 c = p.position - p.up * kRest_m, f = p.forward, s = p.forward.cross(p.up);
        // First vertex ahead of the centroid (the driving direction).
        count = put_face_group(out, "spawn_" + std::to_string(i),
                               {c + f * 2.0, c - f - s * 1.5, c - f + s * 1.5}, count);
    }
    const Vec3 k(track.bounds.min.x(), track.kill_height_m, track.bounds.min.z());
    put_face_group(out, "kill_height", {k, k + Vec3(0, 0, 1), k + Vec3(1, 0, 0)}, count);
    return out;
}

}  // namespace jetrace
