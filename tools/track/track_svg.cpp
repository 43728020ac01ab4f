#include "track_svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace jetrace::tools {
namespace {

struct Frame {
    double min_x = 0, min_z = 0, scale = 1;  // px per m
    int width = 0, height = 0;
    double x(double wx) const { return (wx - min_x) * scale; }
    double y(double wz) const { return (wz - min_z) * scale; }
};

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    return buf;
}

std::string xml_escape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '&') out += "&amp;";
        else if (c == '"') out += "&quot;";
        else out += c;
    }
    return out;
}

// Cells of 2 px: 1 = floor (|normal.y| >= 0.5), 2 = wall; one <rect> per run.
void mesh_cells(const Track& t, const Frame& f, std::string& out) {
    const double cell_px = 3.0;
    const int cols = static_cast<int>(std::ceil(f.width / cell_px));
    const int rows = static_cast<int>(std::ceil(f.height / cell_px));
    std::vector<unsigned char> kind(static_cast<std::size_t>(cols) * rows, 0);
    auto cell = [&](double px, int n) { return std::clamp(static_cast<int>(px / cell_px), 0, n - 1); };
    for (const Triangle& tri : t.triangles) {
        const Aabb b = tri.bounds();
        const unsigned char k = std::abs(tri.normal().y()) >= 0.5 ? 1 : 2;
        const int c0 = cell(f.x(b.min.x()), cols), c1 = cell(f.x(b.max.x()), cols);
        const int r0 = cell(f.y(b.min.z()), rows), r1 = cell(f.y(b.max.z()), rows);
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c) kind[static_cast<std::size_t>(r) * cols + c] |= k;
    }
    const char* fill[] = {"", "#e2e2e2", "#a0a0a0", "#a0a0a0"};
    for (int r = 0; r < rows; ++r) {
        for (int c = 0; c < cols;) {
            const unsigned char k = kind[static_cast<std::size_t>(r) * cols + c];
            int e = c + 1;
            while (e < cols && kind[static_cast<std::size_t>(r) * cols + e] == k) ++e;
            if (k != 0) {
                out += "<rect x=\"" + num(c * cell_px) + "\" y=\"" + num(r * cell_px) + "\" width=\"" +
                       num((e - c) * cell_px) + "\" height=\"" + num(cell_px) + "\" fill=\"" + fill[k] + "\"/>\n";
            }
            c = e;
        }
    }
}

void route_line(const TrackReport& report, const Frame& f, std::string& out) {
    if (report.route.size() < 2) return;
    out += "<polygon fill=\"none\" stroke=\"#2a6fdb\" stroke-width=\"1.5\" points=\"";
    for (const Vec3& p : report.route) out += num(f.x(p.x())) + "," + num(f.y(p.z())) + " ";
    out += "\"/>\n";
}

std::string line(const Frame& f, const Vec3& a, const Vec3& b, const char* colour, const char* extra) {
    return "<line x1=\"" + num(f.x(a.x())) + "\" y1=\"" + num(f.y(a.z())) + "\" x2=\"" + num(f.x(b.x())) +
           "\" y2=\"" + num(f.y(b.z())) + "\" stroke=\"" + colour + "\" " + extra + "/>\n";
}

void gates(const Track& t, const Frame& f, std::string& out) {
    for (std::size_t i = 0; i < t.checkpoints.size(); ++i) {
        const Checkpoint& c = t.checkpoints[i];
        const Vec3 a = c.center - c.across * c.half_width_m, b = c.center + c.across * c.half_width_m;
        const Vec3 tip = c.center + c.normal * std::max(6.0, 14.0 / f.scale);
        const char* colour = i == 0 ? "#101010" : "#d62728";
        out += line(f, a, b, colour, "stroke-width=\"2\"");
        out += line(f, c.center, tip, colour, "stroke-width=\"1.5\" marker-end=\"url(#arrow)\"");
        out += "<text x=\"" + num(f.x(b.x()) + 3) + "\" y=\"" + num(f.y(b.z()) - 3) + "\" fill=\"" + colour + "\">" +
               std::to_string(i) + "</text>\n";
    }
}

void spawns(const Track& t, const Frame& f, std::string& out) {
    for (const Pose& p : t.spawns) {
        out += "<circle cx=\"" + num(f.x(p.position.x())) + "\" cy=\"" + num(f.y(p.position.z())) + "\" r=\"" +
               num(std::max(2.0, 2.5 * f.scale)) + "\" fill=\"#2ca02c\"/>\n";
        out += line(f, p.position, p.position + p.forward * 4.0, "#2ca02c", "stroke-width=\"1.5\"");
    }
}

// Speed buckets of the traces' colours: blue (slowest) through to red.
constexpr int kSpeedColours = 16;
std::string speed_colour(int bucket) {
    char buf[16];
    const double u = static_cast<double>(bucket) / (kSpeedColours - 1);
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", static_cast<int>(40 + 215 * u),
                  static_cast<int>(60 + 120 * (1 - std::abs(2 * u - 1))), static_cast<int>(40 + 215 * (1 - u)));
    return buf;
}

// One polyline per run of points in the same speed bucket.
void trace_lines(const SvgTrace& t, const Frame& f, double lo, double hi, std::string& out) {
    const auto bucket = [&](double v) {
        return std::clamp(static_cast<int>((v - lo) / std::max(hi - lo, 1e-9) * (kSpeedColours - 1) + 0.5), 0,
                          kSpeedColours - 1);
    };
    std::size_t i = 0;
    while (i + 1 < t.points.size()) {
        const int b = bucket(t.speeds_mps[i]);
        std::size_t e = i + 1;
        while (e + 1 < t.points.size() && bucket(t.speeds_mps[e]) == b) ++e;
        out += "<polyline fill=\"none\" stroke-width=\"2\" stroke-linejoin=\"round\" stroke=\"" + speed_colour(b) +
               "\" points=\"";
        for (std::size_t k = i; k <= e; ++k) out += num(f.x(t.points[k].x())) + "," + num(f.y(t.points[k].z())) + " ";
        out += "\"/>\n";
        i = e;
    }
    if (t.points.empty()) return;
    const Vec3& last = t.points.back();
    out += "<text x=\"" + num(f.x(last.x()) + 4) + "\" y=\"" + num(f.y(last.z()) + 4) + "\" fill=\"#202020\">" +
           xml_escape(t.name) + "</text>\n";
}

void speed_legend(double lo, double hi, std::string& out) {
    out += "<text x=\"10\" y=\"18\" fill=\"#202020\">speed " + num(lo) + " m/s</text>\n";
    for (int b = 0; b < kSpeedColours; ++b) {
        out += "<rect x=\"" + std::to_string(110 + 8 * b) + "\" y=\"8\" width=\"8\" height=\"12\" fill=\"" +
               speed_colour(b) + "\"/>\n";
    }
    out += "<text x=\"" + std::to_string(116 + 8 * kSpeedColours) + "\" y=\"18\" fill=\"#202020\">" + num(hi) +
           " m/s</text>\n";
}

// What the picture shows: the route, gates and spawns with a margin (a level
// may sit on a ground plane kilometres wide), else the whole mesh.
Aabb frame_box(const Track& t, const TrackReport& r, std::span<const SvgTrace> traces) {
    std::vector<Vec3> pts = r.route;
    for (const SvgTrace& tr : traces) pts.insert(pts.end(), tr.points.begin(), tr.points.end());
    for (const Checkpoint& c : t.checkpoints) pts.push_back(c.center);
    for (const Pose& p : t.spawns) pts.push_back(p.position);
    if (pts.empty()) return t.bounds;
    Aabb box{pts[0], pts[0]};
    for (const Vec3& p : pts) box.expand(p);
    const Vec3 pad = Vec3::Constant(std::max(40.0, 0.15 * (box.max - box.min).maxCoeff()));
    return {box.min - pad, box.max + pad};
}

}  // namespace

std::string render_svg(const Track& track, const TrackReport& report, int width_px) {
    return render_svg(track, report, width_px, {});
}

std::string render_svg(const Track& track, const TrackReport& report, int width_px, std::span<const SvgTrace> traces) {
    const double margin_m = 10;
    const Aabb b = frame_box(track, report, traces);
    const double span_x = b.max.x() - b.min.x() + 2 * margin_m, span_z = b.max.z() - b.min.z() + 2 * margin_m;
    Frame f;
    f.min_x = b.min.x() - margin_m;
    f.min_z = b.min.z() - margin_m;
    f.scale = width_px / span_x;
    f.width = width_px;
    f.height = std::clamp(static_cast<int>(std::ceil(span_z * f.scale)), 1, 20000);
    std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(f.width) + "\" height=\"" +
                      std::to_string(f.height) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    out += "<title>" + xml_escape(track.name) + ": " + std::to_string(track.triangles.size()) + " triangles, " +
           std::to_string(track.checkpoints.size()) + " gates, " + std::to_string(track.spawns.size()) +
           " spawns (seen from above: x right, z down)</title>\n";
    out += "<defs><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"8\" refY=\"5\" markerWidth=\"6\" "
           "markerHeight=\"6\" orient=\"auto\"><path d=\"M0,0 L10,5 L0,10 z\" fill=\"#d62728\"/></marker></defs>\n";
    out += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    mesh_cells(track, f, out);
    route_line(report, f, out);
    gates(track, f, out);
    spawns(track, f, out);
    if (!traces.empty()) {
        double lo = 1e300, hi = 0;
        for (const SvgTrace& t : traces) {
            for (double v : t.speeds_mps) lo = std::min(lo, v), hi = std::max(hi, v);
        }
        lo = std::min(lo, hi);
        for (const SvgTrace& t : traces) trace_lines(t, f, lo, hi, out);
        speed_legend(lo, hi, out);
    }
    out += "</svg>\n";
    return out;
}

}  // namespace jetrace::tools
