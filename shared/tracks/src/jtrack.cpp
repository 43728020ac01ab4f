// .jtrack encoding and decoding (layout: docs/TRACKS.md, "Compiled tracks").
//
// Header (64 bytes, little-endian):
//    0  magic "JTRACK\r\n"        8  u32 version (1)     12  u32 header bytes (64)
//   16  u64 file bytes            24  u32 name bytes     28  u32 vertex count
//   32  u32 triangle count        36  u32 gate count     40  u32 spawn count
//   44  u32 flags (0)             48  f64 kill height    56  u32 CRC-32C of bytes [64, file bytes)
//   60  u32 CRC-32C of bytes [0, 60)
// then the sections, each padded with zero bytes to a multiple of 8: name,
// vertices (3 f64 each), triangles (3 u32 vertex indices each), gates
// (23 f64 each), spawns (9 f64 each).
#include "jetrace/tracks/jtrack.hpp"

#include "jetrace/core/crc32c.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numeric>

namespace jetrace {
namespace {

constexpr std::size_t kGateDoubles = 23;
constexpr std::size_t kPoseDoubles = 9;

std::uint64_t pad8(std::uint64_t n) { return (n + 7) & ~std::uint64_t{7}; }

// The section sizes a header's counts imply (unit: bytes); every count is
// bounded first, so no sum can overflow.
struct Layout {
    std::uint64_t name = 0, vertices = 0, triangles = 0, gates = 0, spawns = 0;
    std::uint64_t total() const { return kJtrackHeaderBytes + name + vertices + triangles + gates + spawns; }
};

Layout layout_for(std::uint64_t name, std::uint64_t vertices, std::uint64_t triangles, std::uint64_t gates,
                  std::uint64_t spawns) {
    return {pad8(name), vertices * 24, pad8(triangles * 12), gates * kGateDoubles * 8, spawns * kPoseDoubles * 8};
}

// Little-endian writer.
class Out {
public:
    explicit Out(std::size_t size) : bytes_(size, 0) {}
    void u32(std::uint32_t v) {
        for (int i = 0; i < 4; ++i) bytes_[at_++] = static_cast<std::uint8_t>(v >> (8 * i));
    }
    void u64(std::uint64_t v) {
        for (int i = 0; i < 8; ++i) bytes_[at_++] = static_cast<std::uint8_t>(v >> (8 * i));
    }
    void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
    void vec3(const Vec3& v) {
        f64(v.x());
        f64(v.y());
        f64(v.z());
    }
    void raw(const void* p, std::size_t n) {
        if (n > 0) std::memcpy(bytes_.data() + at_, p, n);
        at_ += n;
    }
    void align8() { at_ = static_cast<std::size_t>(pad8(at_)); }
    void seek(std::size_t at) { at_ = at; }
    std::vector<std::uint8_t>& bytes() { return bytes_; }

private:
    std::vector<std::uint8_t> bytes_;
    std::size_t at_ = 0;
};

std::uint64_t bits_key(const Vec3& v, int axis) { return std::bit_cast<std::uint64_t>(v[axis]); }

// Shared vertices by exact bit pattern, numbered in order of first use, and
// three indices per triangle.
void share_vertices(const Track& t, std::vector<Vec3>& vertices, std::vector<std::uint32_t>& indices) {
    const std::size_t corners = t.triangles.size() * 3;
    const auto corner = [&](std::size_t k) -> const Vec3& {
        const Triangle& tri = t.triangles[k / 3];
        return k % 3 == 0 ? tri.a : (k % 3 == 1 ? tri.b : tri.c);
    };
    std::vector<std::uint32_t> order(corners);
    std::iota(order.begin(), order.end(), 0u);
    const auto less = [&](std::uint32_t l, std::uint32_t r) {
        const Vec3& a = corner(l);
        const Vec3& b = corner(r);
        for (int i = 0; i < 3; ++i) {
            if (bits_key(a, i) != bits_key(b, i)) return bits_key(a, i) < bits_key(b, i);
        }
        return l < r;
    };
    std::sort(order.begin(), order.end(), less);
    // first[k]: the first corner with the same position as corner k.
    std::vector<std::uint32_t> first(corners);
    for (std::size_t i = 0; i < corners; ++i) {
        const bool same = i > 0 && bits_key(corner(order[i - 1]), 0) == bits_key(corner(order[i]), 0) &&
                          bits_key(corner(order[i - 1]), 1) == bits_key(corner(order[i]), 1) &&
                          bits_key(corner(order[i - 1]), 2) == bits_key(corner(order[i]), 2);
        first[order[i]] = same ? first[order[i - 1]] : order[i];
    }
    indices.assign(corners, 0);
    vertices.clear();
    std::vector<std::uint32_t> id(corners, 0);
    for (std::size_t k = 0; k < corners; ++k) {
        if (first[k] == k) {
            id[k] = static_cast<std::uint32_t>(vertices.size());
            vertices.push_back(corner(k));
        }
        indices[k] = id[first[k]];
    }
}

}  // namespace

bool is_jtrack(std::span<const std::uint8_t> bytes) {
    return bytes.size() >= sizeof kJtrackMagic && std::memcmp(bytes.data(), kJtrackMagic, sizeof kJtrackMagic) == 0;
}

std::vector<std::uint8_t> encode_jtrack(const Track& track) {
    std::vector<Vec3> vertices;
    std::vector<std::uint32_t> indices;
    share_vertices(track, vertices, indices);
    const Layout l = layout_for(track.name.size(), vertices.size(), track.triangles.size(), track.checkpoints.size(),
                                track.spawns.size());
    Out o(static_cast<std::size_t>(l.total()));
    o.raw(kJtrackMagic, sizeof kJtrackMagic);
    o.u32(kJtrackVersion);
    o.u32(static_cast<std::uint32_t>(kJtrackHeaderBytes));
    o.u64(l.total());
    o.u32(static_cast<std::uint32_t>(track.name.size()));
    o.u32(static_cast<std::uint32_t>(vertices.size()));
    o.u32(static_cast<std::uint32_t>(track.triangles.size()));
    o.u32(static_cast<std::uint32_t>(track.checkpoints.size()));
    o.u32(static_cast<std::uint32_t>(track.spawns.size()));
    o.u32(0);
    o.f64(track.kill_height_m);
    o.seek(kJtrackHeaderBytes);
    o.raw(track.name.data(), track.name.size());
    o.align8();
    for (const Vec3& v : vertices) o.vec3(v);
    for (std::uint32_t i : indices) o.u32(i);
    o.align8();
    for (const Checkpoint& c : track.checkpoints) {
        for (const Vec3* v : {&c.center, &c.normal, &c.across, &c.up}) o.vec3(*v);
        o.f64(c.half_width_m);
        o.f64(c.half_height_m);
        for (const Vec3* v : {&c.respawn.position, &c.respawn.forward, &c.respawn.up}) o.vec3(*v);
    }
    for (const Pose& p : track.spawns) {
        for (const Vec3* v : {&p.position, &p.forward, &p.up}) o.vec3(*v);
    }
    std::vector<std::uint8_t>& b = o.bytes();
    const std::uint32_t payload = crc32c(std::span<const std::uint8_t>(b).subspan(kJtrackHeaderBytes));
    o.seek(56);
    o.u32(payload);
    o.u32(crc32c(std::span<const std::uint8_t>(b.data(), 60)));
    return std::move(b);
}

}  // namespace jetrace
