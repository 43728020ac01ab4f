// Decoding a .jtrack file (layout: jtrack.cpp and docs/TRACKS.md). Order of
// checks: header size, magic, version, header checksum, every count against
// its limit, the file size the counts imply against the header's and the
// real one, the payload checksum, padding, then every value: vertices finite
// and in range, indices below the vertex count, the name, and the rules of
// the track (validate_rules: gates, spawns, kill height).
#include "jetrace/tracks/jtrack.hpp"

#include "jetrace/core/crc32c.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sys/mman.h>

namespace jetrace {
namespace {

// Little-endian reader over bytes already checked to hold what is read.
class In {
public:
    In(std::span<const std::uint8_t> b, std::size_t at) : b_(b), at_(at) {}
    std::uint32_t u32() {
        std::uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(b_[at_++]) << (8 * i);
        return v;
    }
    std::uint64_t u64() {
        std::uint64_t v = 0;
        for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(b_[at_++]) << (8 * i);
        return v;
    }
    double f64() { return std::bit_cast<double>(u64()); }
    Vec3 vec3() {
        const double x = f64();
        const double y = f64();
        return {x, y, f64()};
    }
    std::size_t at() const { return at_; }
    // Skips to the next multiple of 8; false if a skipped byte is not zero.
    bool align8() {
        for (; at_ % 8 != 0; ++at_) {
            if (b_[at_] != 0) return false;
        }
        return true;
    }

private:
    std::span<const std::uint8_t> b_;
    std::size_t at_;
};

struct Header {
    std::uint32_t version = 0, header_bytes = 0, name = 0, vertices = 0, triangles = 0, gates = 0, spawns = 0,
                  flags = 0, payload_crc = 0, header_crc = 0;
    std::uint64_t file_bytes = 0;
    double kill_height_m = 0;
};

Header read_header(std::span<const std::uint8_t> b) {
    In in(b, 8);
    Header h;
    h.version = in.u32();
    h.header_bytes = in.u32();
    h.file_bytes = in.u64();
    h.name = in.u32();
    h.vertices = in.u32();
    h.triangles = in.u32();
    h.gates = in.u32();
    h.spawns = in.u32();
    h.flags = in.u32();
    h.kill_height_m = in.f64();
    h.payload_crc = in.u32();
    h.header_crc = in.u32();
    return h;
}

std::string hex(std::uint32_t v) {
    char s[11];
    std::snprintf(s, sizeof s, "0x%08x", v);
    return s;
}

std::uint64_t pad8(std::uint64_t n) { return (n + 7) & ~std::uint64_t{7}; }

// Checks the header against its limits and the file size. Empty if fine.
std::string check_header(std::span<const std::uint8_t> b, const Header& h) {
    const std::string n = std::to_string(b.size());
    if (h.version != kJtrackVersion) {
        return "unsupported version " + std::to_string(h.version) + " (this reader reads version " +
               std::to_string(kJtrackVersion) + ")";
    }
    if (h.header_bytes != kJtrackHeaderBytes) return "header size " + std::to_string(h.header_bytes) + " is not 64";
    if (const std::uint32_t c = crc32c(b.first(60)); c != h.header_crc) {
        return "header checksum mismatch (stored " + hex(h.header_crc) + ", computed " + hex(c) + ")";
    }
    if (h.flags != 0) return "unknown flags " + hex(h.flags) + " (must be 0)";
    if (h.name > kJtrackMaxNameBytes) return "name of " + std::to_string(h.name) + " bytes exceeds 4096";
    if (h.triangles == 0) return "no triangles";
    if (h.triangles > kMaxTrackTriangles) {
        return std::to_string(h.triangles) + " triangles exceed the limit of " + std::to_string(kMaxTrackTriangles);
    }
    if (h.vertices == 0 || h.vertices > 3ull * h.triangles) {
        return "vertex count " + std::to_string(h.vertices) + " is not in 1.." + std::to_string(3ull * h.triangles) +
               " (three per triangle at most)";
    }
    if (h.gates > kJtrackMaxGates) return std::to_string(h.gates) + " gates exceed the limit of 100000";
    if (h.spawns > kJtrackMaxSpawns) return std::to_string(h.spawns) + " spawns exceed the limit of 100000";
    const std::uint64_t want = kJtrackHeaderBytes + pad8(h.name) + 24ull * h.vertices + pad8(12ull * h.triangles) +
                               184ull * h.gates + 72ull * h.spawns;
    if (h.file_bytes != want) {
        return "header says " + std::to_string(h.file_bytes) + " bytes but its counts make " + std::to_string(want);
    }
    if (b.size() != want) return "file is " + n + " bytes but its header says " + std::to_string(want) + " (truncated or padded)";
    if (const std::uint32_t c = crc32c(b.subspan(kJtrackHeaderBytes)); c != h.payload_crc) {
        return "payload checksum mismatch (stored " + hex(h.payload_crc) + ", computed " + hex(c) + ")";
    }
    return {};
}

bool in_range(const Vec3& v) {
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(v[i]) || std::abs(v[i]) > kMaxTrackCoordinate_m) return false;
    }
    return true;
}

// Asks for transparent huge pages under the not yet written storage of a
// large array: a 2 M-triangle track's 168 MB then takes about 80 page
// faults instead of 41,000. Advisory; ignored where not supported.
void advise_huge_pages(const void* data, std::size_t bytes) {
    constexpr std::uintptr_t kHuge = std::uintptr_t{2} << 20;
    const auto begin = (reinterpret_cast<std::uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
    const auto end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(kHuge - 1);
    if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
}

// Reads the name, vertices and triangles into `out` (bounds as make_track
// computes them). Empty if fine.
std::string read_mesh(In& in, std::span<const std::uint8_t> b, const Header& h, Track& out) {
    out.name.assign(reinterpret_cast<const char*>(b.data() + in.at()), h.name);
    for (std::size_t i = 0; i < out.name.size(); ++i) {
        const auto c = static_cast<unsigned char>(out.name[i]);
        if (c < 0x20 || c == 0x7f) return "name byte " + std::to_string(i) + " is a control character";
    }
    In skip(b, in.at() + h.name);
    if (!skip.align8()) return "name padding is not zero";
    in = skip;
    std::vector<Vec3> vertices(h.vertices);
    for (std::uint32_t i = 0; i < h.vertices; ++i) {
        vertices[i] = in.vec3();
        if (!in_range(vertices[i])) {
            return "vertex " + std::to_string(i) + " has a coordinate that is not finite or exceeds 1e6 m";
        }
    }
    out.triangles.reserve(h.triangles);
    advise_huge_pages(out.triangles.data(), h.triangles * sizeof(Triangle));
    for (std::uint32_t t = 0; t < h.triangles; ++t) {
        std::uint32_t corner[3];
        for (std::uint32_t& k : corner) {
            k = in.u32();
            if (k >= h.vertices) {
                return "triangle " + std::to_string(t) + " uses vertex " + std::to_string(k) + " of " +
                       std::to_string(h.vertices);
            }
        }
        add_triangle(out, vertices[corner[0]], vertices[corner[1]], vertices[corner[2]]);
    }
    if (!in.align8()) return "triangle padding is not zero";
    out.kill_height_m = h.kill_height_m;
    return {};
}

}  // namespace

bool decode_jtrack(std::span<const std::uint8_t> bytes, Track& out, std::string& error) {
    if (bytes.size() < kJtrackHeaderBytes) {
        error = "file is " + std::to_string(bytes.size()) + " bytes, shorter than the 64-byte .jtrack header";
        return false;
    }
    if (!is_jtrack(bytes)) {
        error = "not a .jtrack file (bad magic)";
        return false;
    }
    const Header h = read_header(bytes);
    if (error = check_header(bytes, h); !error.empty()) return false;
    In in(bytes, kJtrackHeaderBytes);
    Track t;
    if (error = read_mesh(in, bytes, h, t); !error.empty()) return false;
    t.checkpoints.resize(h.gates);
    for (Checkpoint& c : t.checkpoints) {
        for (Vec3* v : {&c.center, &c.normal, &c.across, &c.up}) *v = in.vec3();
        c.half_width_m = in.f64();
        c.half_height_m = in.f64();
        for (Vec3* v : {&c.respawn.position, &c.respawn.forward, &c.respawn.up}) *v = in.vec3();
    }
    t.spawns.resize(h.spawns);
    for (Pose& p : t.spawns) {
        for (Vec3* v : {&p.position, &p.forward, &p.up}) *v = in.vec3();
    }
    // Every corner is a checked vertex: the rest of validate() remains.
    if (error = validate_rules(t); !error.empty()) {
        error = "track does not validate: " + error;
        return false;
    }
    out = std::move(t);
    return true;
}

}  // namespace jetrace
