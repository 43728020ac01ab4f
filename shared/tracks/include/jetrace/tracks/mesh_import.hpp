// Meshes as modelling tools export them: glTF 2.0 (.gltf + .bin, .glb),
// read into named parts of world-space triangles. Untrusted input: every
// index, offset, stride and count is checked; problems come back as a
// message, never an assert or a crash. docs/TRACKS.md, "glTF".
#pragma once

#include "jetrace/core/math.hpp"

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace jetrace {

/// One node's triangles (or one OBJ group's), in world space.
struct MeshPart {
    /// The node's name (else its mesh's, else "node<i>").
    std::string name;
    /// Three corners per triangle, in file order.
    std::vector<Vec3> corners;
};

struct ImportedMesh {
    std::vector<MeshPart> parts;
    /// Primitives that are not triangle lists (points, lines, strips, fans).
    std::size_t skipped_primitives = 0;
    std::size_t triangles() const;
};

/// Largest mesh or manifest file read, checked before parsing (unit: bytes).
inline constexpr std::size_t kMaxTrackFileBytes = std::size_t{1} << 30;

/// Reads a .gltf (its .bin files beside it) or a .glb. Nodes of every scene
/// (the default scene's when it names one) with their transforms applied;
/// indexed and non-indexed TRIANGLES primitives; Y up, as glTF specifies.
bool import_gltf_file(const std::string& path, ImportedMesh& out, std::string& error);

/// The same from bytes in memory (GLB when they start with "glTF", else
/// JSON); external buffers are looked up in `base_dir` ("" : none allowed).
bool import_gltf_bytes(std::string_view bytes, const std::string& base_dir, ImportedMesh& out, std::string& error);

}  // namespace jetrace
