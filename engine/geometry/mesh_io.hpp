// Reading and writing triangle meshes: Wavefront OBJ (through tinyobjloader) and STL, ASCII or
// binary (a short reader of our own: the format is a fixed 50-byte record or five keywords,
// and Debian's alternative, assimp, would pull in a large dependency for it).
//
// Files carry no unit, so the caller declares it (CT segmentation exports are usually in
// millimetres). Coordinates are held in single precision on the way in and out (binary STL's
// own precision, 3 nm at 50 mm), so an OBJ and an STL of the same mesh load to the same
// bits; duplicate vertices are welded (STL shares none), so both give the same indexed mesh.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "engine/geometry/triangle_mesh.hpp"

namespace acdr {

enum class LengthUnit { kMillimetre, kMetre };

/// Metres per file unit: 1e-3 for millimetres, 1 for metres.
double metres_per_unit(LengthUnit unit);

enum class MeshFormat { kObj, kStlAscii, kStlBinary };

/// Parses OBJ text (v and f lines; polygons are triangulated, other statements ignored).
/// Errors name the file and line: "spine.obj:17: vertex has 2 coordinates (expected 3)".
std::optional<TriangleMesh> read_obj(std::string_view text, const std::string& name,
                                     LengthUnit unit, std::string* error);

/// Parses STL bytes, binary or ASCII (binary when the size is exactly 84 + 50 N for the N
/// triangles its header declares). Errors name the file and the line (ASCII) or byte offset
/// (binary): "c4.stl: byte 1234: triangle 24 vertex 2 is not a finite number".
std::optional<TriangleMesh> read_stl(std::string_view bytes, const std::string& name,
                                     LengthUnit unit, std::string* error);

/// Loads a mesh file, choosing the reader by extension (.obj or .stl, any case). Does not
/// check that the mesh is closed; see `load_closed_mesh_file`.
std::optional<TriangleMesh> load_mesh_file(const std::string& path, LengthUnit unit,
                                           std::string* error);

/// Loads a mesh file and requires a closed, outward, non-degenerate surface (a bone).
/// The error starts with the path: "c5.stl: not a closed surface: 12 open edges, ...".
std::optional<TriangleMesh> load_closed_mesh_file(const std::string& path, LengthUnit unit,
                                                  std::string* error);

/// Writes the mesh (SI metres) to `path` in `unit`. Returns false with a message on failure.
bool save_mesh_file(const TriangleMesh& mesh, const std::string& path, MeshFormat format,
                    LengthUnit unit, std::string* error);

/// The file bytes `save_mesh_file` would write.
std::string mesh_file_bytes(const TriangleMesh& mesh, MeshFormat format, LengthUnit unit);

}  // namespace acdr
