// glTF 2.0 import with tinygltf (Debian's libtinygltf: the implementation is
// in the shared library, so no TINYGLTF_IMPLEMENTATION here). tinygltf parses
// the JSON and loads the buffers; everything it hands back is checked again
// here before a byte is read: accessor, buffer view and buffer indices,
// offsets, strides and counts against the buffer's real size, component
// types, index values, node transforms. Images are never decoded.
#include "jetrace/core/track.hpp"
#include "jetrace/tracks/mesh_import.hpp"

#include "gltf_files.hpp"

#include <tiny_gltf.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>

namespace jetrace {
namespace {

using namespace detail::gltf_files;

using Mat4 = Eigen::Matrix4d;

bool fail(std::string& error, std::string message) {
    error = std::move(message);
    return false;
}

// -------------------------------------------------------------- accessors

struct View {
    const unsigned char* base = nullptr;  // first element
    std::size_t count = 0, stride = 0;
};

// Checks an accessor of `components` values of `comp_size` bytes each and
// returns where its elements are. Every offset is checked against the real
// buffer size in 64-bit arithmetic (sizes are bounded by kMaxTrackFileBytes).
bool accessor_view(const tinygltf::Model& m, int index, int type, std::size_t comp_size, View& v, std::string& what) {
    if (index < 0 || static_cast<std::size_t>(index) >= m.accessors.size()) return fail(what, "accessor index out of range");
    const tinygltf::Accessor& a = m.accessors[index];
    if (a.sparse.isSparse) return fail(what, "sparse accessors are not supported");
    if (a.type != type) return fail(what, "accessor " + std::to_string(index) + " has the wrong type");
    if (a.bufferView < 0 || static_cast<std::size_t>(a.bufferView) >= m.bufferViews.size()) {
        return fail(what, "accessor " + std::to_string(index) + " has no valid bufferView");
    }
    const tinygltf::BufferView& bv = m.bufferViews[a.bufferView];
    if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= m.buffers.size()) {
        return fail(what, "bufferView " + std::to_string(a.bufferView) + " names no buffer");
    }
    const std::vector<unsigned char>& data = m.buffers[bv.buffer].data;
    const std::size_t elem = comp_size * static_cast<std::size_t>(type == TINYGLTF_TYPE_VEC3 ? 3 : 1);
    const std::size_t stride = bv.byteStride == 0 ? elem : bv.byteStride;
    const std::size_t limit = kMaxTrackFileBytes;
    if (bv.byteOffset > limit || bv.byteLength > limit || bv.byteOffset + bv.byteLength > data.size()) {
        return fail(what, "bufferView " + std::to_string(a.bufferView) + " lies outside its buffer");
    }
    if (stride < elem || stride > 252 || a.byteOffset > limit || a.count > limit) {
        return fail(what, "accessor " + std::to_string(index) + " has a bad stride, offset or count");
    }
    if (a.count > 0 && a.byteOffset + stride * (a.count - 1) + elem > bv.byteLength) {
        return fail(what, "accessor " + std::to_string(index) + " reads past the end of its bufferView");
    }
    v.base = data.data() + bv.byteOffset + a.byteOffset;
    v.count = a.count;
    v.stride = stride;
    return true;
}

template <typename T>
T load(const unsigned char* p) {
    T x;
    std::memcpy(&x, p, sizeof x);
    return x;
}

bool read_positions(const tinygltf::Model& m, int index, std::vector<Vec3>& out, std::string& what) {
    View v;
    if (index >= 0 && static_cast<std::size_t>(index) < m.accessors.size() &&
        m.accessors[index].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
        return fail(what, "POSITION accessor " + std::to_string(index) + " is not float");
    }
    if (!accessor_view(m, index, TINYGLTF_TYPE_VEC3, 4, v, what)) return false;
    out.resize(v.count);
    for (std::size_t i = 0; i < v.count; ++i) {
        const unsigned char* p = v.base + i * v.stride;
        out[i] = Vec3(load<float>(p), load<float>(p + 4), load<float>(p + 8));
        if (!std::isfinite(out[i].x()) || !std::isfinite(out[i].y()) || !std::isfinite(out[i].z())) {
            return fail(what, "POSITION " + std::to_string(i) + " is not finite");
        }
    }
    return true;
}

bool read_indices(const tinygltf::Model& m, int index, std::vector<std::uint32_t>& out, std::string& what) {
    if (index < 0 || static_cast<std::size_t>(index) >= m.accessors.size()) return fail(what, "indices accessor out of range");
    const int ct = m.accessors[index].componentType;
    const std::size_t size = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                             : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                             : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                            : 0;
    if (size == 0) return fail(what, "indices accessor " + std::to_string(index) + " is not an unsigned integer type");
    View v;
    if (!accessor_view(m, index, TINYGLTF_TYPE_SCALAR, size, v, what)) return false;
    out.resize(v.count);
    for (std::size_t i = 0; i < v.count; ++i) {
        const unsigned char* p = v.base + i * v.stride;
        out[i] = size == 1 ? *p : size == 2 ? load<std::uint16_t>(p) : load<std::uint32_t>(p);
    }
    return true;
}

// ------------------------------------------------------------ hierarchy

bool finite_all(const std::vector<double>& v) {
    for (double x : v)
        if (!std::isfinite(x)) return false;
    return true;
}

bool local_matrix(const tinygltf::Node& n, Mat4& out, std::string& what) {
    out.setIdentity();
    if (!n.matrix.empty()) {
        if (n.matrix.size() != 16 || !finite_all(n.matrix)) return fail(what, "a matrix needs 16 finite numbers");
        for (int i = 0; i < 16; ++i) out(i % 4, i / 4) = n.matrix[i];  // column-major
        return true;
    }
    if ((!n.translation.empty() && n.translation.size() != 3) || (!n.rotation.empty() && n.rotation.size() != 4) ||
        (!n.scale.empty() && n.scale.size() != 3) || !finite_all(n.translation) || !finite_all(n.rotation) ||
        !finite_all(n.scale)) {
        return fail(what, "translation, rotation or scale is malformed or not finite");
    }
    Mat4 t = Mat4::Identity(), r = Mat4::Identity(), s = Mat4::Identity();
    if (!n.translation.empty()) t.block<3, 1>(0, 3) = Vec3(n.translation[0], n.translation[1], n.translation[2]);
    if (!n.rotation.empty()) {
        Eigen::Quaterniond q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
        if (!(q.norm() > 1e-6)) return fail(what, "rotation quaternion has zero length");
        r.block<3, 3>(0, 0) = q.normalized().toRotationMatrix();
    }
    if (!n.scale.empty()) s.diagonal().head<3>() = Vec3(n.scale[0], n.scale[1], n.scale[2]);
    out = t * r * s;
    return true;
}

struct Walk {
    const tinygltf::Model& m;
    ImportedMesh& out;
    std::size_t triangles = 0;
};

bool add_primitive(Walk& w, const tinygltf::Primitive& p, const Mat4& world, MeshPart& part, std::string& what) {
    if (p.mode != TINYGLTF_MODE_TRIANGLES) {
        ++w.out.skipped_primitives;
        return true;
    }
    const auto pos = p.attributes.find("POSITION");
    if (pos == p.attributes.end()) return fail(what, "a primitive has no POSITION");
    // The declared count, before any vertex is read.
    const int counted = p.indices >= 0 ? p.indices : pos->second;
    if (counted < 0 || static_cast<std::size_t>(counted) >= w.m.accessors.size()) return fail(what, "accessor index out of range");
    if (w.m.accessors[counted].count / 3 > kMaxTrackTriangles - w.triangles) {
        return fail(what, "more than " + std::to_string(kMaxTrackTriangles) + " triangles in the file");
    }
    std::vector<Vec3> verts;
    std::vector<std::uint32_t> idx;
    if (!read_positions(w.m, pos->second, verts, what)) return false;
    if (p.indices >= 0) {
        if (!read_indices(w.m, p.indices, idx, what)) return false;
    } else {
        idx.resize(verts.size());
        for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<std::uint32_t>(i);
    }
    if (idx.size() % 3 != 0) return fail(what, std::to_string(idx.size()) + " indices: not a multiple of 3");
    w.triangles += idx.size() / 3;
    for (std::size_t i = 0; i < verts.size(); ++i) {
        const Eigen::Vector4d h = world * Eigen::Vector4d(verts[i].x(), verts[i].y(), verts[i].z(), 1.0);
        verts[i] = h.head<3>();
        if (!(verts[i].cwiseAbs().maxCoeff() <= kMaxTrackCoordinate_m)) {
            return fail(what, "a vertex lies beyond 1e6 m (or is not finite) after its transforms");
        }
    }
    for (std::uint32_t i : idx) {
        if (i >= verts.size()) return fail(what, "index " + std::to_string(i) + " is out of range");
        part.corners.push_back(verts[i]);
    }
    return true;
}

// Depth first in the file's child order; a node repeated in the hierarchy
// (a cycle or a shared child) is refused as the glTF spec requires a tree.
bool walk_node(Walk& w, int index, const Mat4& parent, std::vector<char>& seen, int depth, std::string& error) {
    if (index < 0 || static_cast<std::size_t>(index) >= w.m.nodes.size()) return fail(error, "node index out of range");
    std::string what = "node " + std::to_string(index) + " ('" + w.m.nodes[index].name + "'): ";
    if (seen[index] || depth > 64) return fail(error, what + "appears twice in the hierarchy (or nests over 64 deep)");
    seen[index] = 1;
    const tinygltf::Node& n = w.m.nodes[index];
    Mat4 local;
    std::string problem;
    if (!local_matrix(n, local, problem)) return fail(error, what + problem);
    const Mat4 world = parent * local;
    if (n.mesh >= 0) {
        if (static_cast<std::size_t>(n.mesh) >= w.m.meshes.size()) return fail(error, what + "mesh index out of range");
        const tinygltf::Mesh& mesh = w.m.meshes[n.mesh];
        MeshPart part;
        part.name = !n.name.empty() ? n.name : !mesh.name.empty() ? mesh.name : "node" + std::to_string(index);
        for (const tinygltf::Primitive& p : mesh.primitives) {
            if (!add_primitive(w, p, world, part, problem)) return fail(error, what + problem);
        }
        if (!part.corners.empty()) w.out.parts.push_back(std::move(part));
    }
    for (int child : n.children) {
        if (!walk_node(w, child, world, seen, depth + 1, error)) return false;
    }
    return true;
}

bool convert(const tinygltf::Model& m, ImportedMesh& out, std::string& error) {
    Walk w{m, out};
    std::vector<char> seen(m.nodes.size(), 0);
    if (m.scenes.empty()) return fail(error, "the glTF file has no scene");
    const bool one = m.defaultScene >= 0;
    if (one && static_cast<std::size_t>(m.defaultScene) >= m.scenes.size()) return fail(error, "'scene' is out of range");
    for (std::size_t s = 0; s < m.scenes.size(); ++s) {
        if (one && s != static_cast<std::size_t>(m.defaultScene)) continue;
        for (int root : m.scenes[s].nodes) {
            if (!walk_node(w, root, Mat4::Identity(), seen, 0, error)) return false;
        }
    }
    if (out.parts.empty()) return fail(error, "the glTF scene has no triangles");
    return true;
}

}  // namespace

std::size_t ImportedMesh::triangles() const {
    std::size_t n = 0;
    for (const MeshPart& p : parts) n += p.corners.size() / 3;
    return n;
}

bool import_gltf_bytes(std::string_view bytes, const std::string& base_dir, ImportedMesh& out, std::string& error) {
    if (bytes.size() > kMaxTrackFileBytes || bytes.size() > 0xffffffffu) return fail(error, "glTF data too large");
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&no_image, nullptr);
    bool files_allowed = !base_dir.empty();
    loader.SetFsCallbacks({&file_exists, &expand_path, &read_whole, &no_write, &files_allowed});
    tinygltf::Model model;
    std::string err, warn;
    const bool glb = bytes.size() >= 4 && bytes.substr(0, 4) == "glTF";
    const auto size = static_cast<unsigned int>(bytes.size());
    const bool ok = glb ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                                      reinterpret_cast<const unsigned char*>(bytes.data()), size, base_dir)
                        : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, base_dir);
    if (!ok) {
        while (!err.empty() && err.back() == '\n') err.pop_back();
        return fail(error, "glTF: " + (err.empty() ? std::string("cannot parse") : err));
    }
    ImportedMesh mesh;
    if (!convert(model, mesh, error)) return false;
    out = std::move(mesh);
    return true;
}

bool import_gltf_file(const std::string& path, ImportedMesh& out, std::string& error) {
    std::vector<unsigned char> bytes;
    std::string err;
    if (!read_whole(&bytes, &err, path, nullptr)) {
        while (!err.empty() && err.back() == '\n') err.pop_back();
        return fail(error, err);
    }
    const std::string dir = std::filesystem::path(path).parent_path().string();
    const std::string_view view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    if (!import_gltf_bytes(view, dir.empty() ? "." : dir, out, error)) {
        error = path + ": " + error;
        return false;
    }
    return true;
}

}  // namespace jetrace
