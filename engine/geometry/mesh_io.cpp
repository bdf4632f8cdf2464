// OBJ through tinyobjloader, STL (ASCII and binary) by hand; both welded to an indexed mesh.
#include "engine/geometry/mesh_io.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include <tiny_obj_loader.h>

#include "engine/core/input_file.hpp"

namespace acdr {
namespace {

static_assert(std::endian::native == std::endian::little,
              "binary STL is little-endian; this reader copies its floats directly");

/// A file coordinate (single precision, as stored) to metres.
double to_metres(float v, double scale) { return static_cast<double>(v) * scale; }

/// Metres to the single-precision value written to a file.
float to_file(double v_m, double scale) { return static_cast<float>(v_m / scale); }

bool set_error(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// Splits a line into tokens separated by spaces and tabs (as the OBJ reader does: a form feed
/// or another control character is part of a word).
std::vector<std::string_view> tokens_of(std::string_view line) {
  std::vector<std::string_view> out;
  auto blank = [](char c) { return c == ' ' || c == '\t'; };
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !blank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

/// A whole token as a finite number, else nullopt.
std::optional<double> number_of(std::string_view token) {
  const std::string s(token);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

/// Calls `fn(line_number, line)` for each line (1-based), without the line break.
template <class Fn>
void for_each_line(std::string_view text, Fn&& fn) {
  int line_no = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (!fn(++line_no, line)) return;
    start = end + 1;
  }
}

std::string quoted(std::string_view s) {
  std::string out(1, '\'');
  out.append(s.substr(0, 40));
  out.append(s.size() > 40 ? "...'" : "'");
  return out;
}

// ---------------------------------------------------------------------------------------------
// OBJ

/// tinyobjloader reads an unparsable coordinate as 0 and reports an out-of-range face index only
/// as a warning at the last line, so the v and f statements are checked here first, with the
/// line of each problem.
bool check_obj_statements(std::string_view text, const std::string& name, std::string* error) {
  long vertices = 0;
  long total_vertices = 0;
  for_each_line(text, [&](int, std::string_view line) {
    const auto t = tokens_of(line);
    if (!t.empty() && t[0] == "v") ++total_vertices;
    return true;
  });
  std::string message;
  for_each_line(text, [&](int line_no, std::string_view line) {
    const auto t = tokens_of(line);
    if (t.empty()) return true;
    const std::string where = name + ":" + std::to_string(line_no) + ": ";
    if (t[0] == "v") {
      if (t.size() < 4) {
        message = where + "vertex has " + std::to_string(t.size() - 1) +
                  " coordinates (expected x y z)";
        return false;
      }
      for (std::size_t k = 1; k < 4; ++k) {
        const auto x = number_of(t[k]);
        if (!x) {
          message = where + "vertex coordinate " + std::to_string(k) + " is not a finite number (got " +
                    quoted(t[k]) + ")";
          return false;
        }
        // tinyobjloader holds coordinates as 32-bit floats: beyond their range one would be
        // infinite.
        if (!std::isfinite(static_cast<float>(*x))) {
          message = where + "vertex coordinate " + std::to_string(k) +
                    " is outside the range of a 32-bit float (got " + quoted(t[k]) +
                    ", expected at most 3.4e38 in magnitude)";
          return false;
        }
      }
      ++vertices;
    } else if (t[0] == "f") {
      if (t.size() < 4) {
        message = where + "face has " + std::to_string(t.size() - 1) +
                  " vertices (expected at least 3)";
        return false;
      }
      for (std::size_t k = 1; k < t.size(); ++k) {
        // "v", "v/vt", "v//vn" or "v/vt/vn": the vertex index is the first field.
        const std::string_view field = t[k].substr(0, t[k].find('/'));
        char* end = nullptr;
        const std::string s(field);
        const long i = std::strtol(s.c_str(), &end, 10);
        if (s.empty() || end != s.c_str() + s.size()) {
          message = where + "face vertex " + quoted(t[k]) + " is not an index (expected an integer)";
          return false;
        }
        // Positive indices count from 1 over the whole file; negative ones back from here.
        const long resolved = i > 0 ? i : vertices + i + 1;
        const long limit = i > 0 ? total_vertices : vertices;
        if (i == 0 || resolved < 1 || resolved > limit) {
          message = where + "face refers to vertex " + std::to_string(i) + ", but the file has " +
                    std::to_string(limit) + " vertices" + (i < 0 ? " before this line" : "") +
                    " (expected 1 to " + std::to_string(limit) + ", or -1 to -" +
                    std::to_string(vertices) + ")";
          return false;
        }
      }
    }
    return true;
  });
  if (!message.empty()) return set_error(error, message);
  if (total_vertices == 0) return set_error(error, name + ": no vertices ('v' lines) in the OBJ file");
  return true;
}

// ---------------------------------------------------------------------------------------------
// STL

std::optional<TriangleMesh> read_binary_stl(std::string_view bytes, const std::string& name,
                                            double scale, std::string* error) {
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);
  TriangleMesh mesh;
  mesh.vertices.reserve(3 * static_cast<std::size_t>(n));
  mesh.triangles.reserve(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    const std::size_t record = 84 + 50 * static_cast<std::size_t>(t);
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = record + 12 + 12 * static_cast<std::size_t>(k);
      float xyz[3];
      std::memcpy(xyz, bytes.data() + at, sizeof xyz);
      if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2])) {
        set_error(error, name + ": byte " + std::to_string(at) + ": triangle " + std::to_string(t) +
                             " vertex " + std::to_string(k + 1) +
                             " is not a finite number (expected x y z as 32-bit floats)");
        return std::nullopt;
      }
      mesh.vertices.emplace_back(to_metres(xyz[0], scale), to_metres(xyz[1], scale),
                                 to_metres(xyz[2], scale));
    }
    mesh.triangles.push_back({base, base + 1, base + 2});
  }
  return mesh;
}

std::optional<TriangleMesh> read_ascii_stl(std::string_view text, const std::string& name,
                                           double scale, std::string* error) {
  // Grammar per solid: solid [name] { facet normal n n n / outer loop / vertex x y z (x3) /
  // endloop / endfacet } endsolid [name]. Several solids in one file are accepted.
  enum class State { kOutside, kInSolid, kInFacet, kInLoop, kLoopDone };
  State state = State::kOutside;
  TriangleMesh mesh;
  int loop_vertices = 0;
  int last_line = 0;
  std::string message;
  for_each_line(text, [&](int line_no, std::string_view line) {
    last_line = line_no;
    const auto t = tokens_of(line);
    if (t.empty()) return true;
    const std::string where = name + ":" + std::to_string(line_no) + ": ";
    const std::string word = lower(std::string(t[0]));
    auto expect = [&](const char* what) {
      message = where + "unexpected " + quoted(t[0]) + " (expected " + what + ")";
      return false;
    };
    switch (state) {
      case State::kOutside:
        if (word != "solid") return expect("'solid'");
        state = State::kInSolid;
        return true;
      case State::kInSolid:
        if (word == "endsolid") {
          state = State::kOutside;
          return true;
        }
        if (word != "facet") return expect("'facet' or 'endsolid'");
        state = State::kInFacet;
        return true;
      case State::kInFacet:
        if (word != "outer" || t.size() < 2 || lower(std::string(t[1])) != "loop")
          return expect("'outer loop'");
        state = State::kInLoop;
        loop_vertices = 0;
        return true;
      case State::kInLoop: {
        if (word == "endloop") {
          if (loop_vertices != 3) {
            message = where + "facet has " + std::to_string(loop_vertices) +
                      " vertices (expected 3)";
            return false;
          }
          const auto base = static_cast<std::uint32_t>(mesh.vertices.size() - 3);
          mesh.triangles.push_back({base, base + 1, base + 2});
          state = State::kLoopDone;
          return true;
        }
        if (word != "vertex") return expect("'vertex' or 'endloop'");
        if (t.size() != 4) {
          message = where + "vertex has " + std::to_string(t.size() - 1) +
                    " coordinates (expected x y z)";
          return false;
        }
        if (++loop_vertices > 3) {
          message = where + "facet has more than 3 vertices (expected 3)";
          return false;
        }
        Vec3 v;
        for (int k = 0; k < 3; ++k) {
          const auto x = number_of(t[k + 1]);
          if (!x) {
            message = where + "vertex coordinate " + std::to_string(k + 1) +
                      " is not a finite number (got " + quoted(t[k + 1]) + ")";
            return false;
          }
          // Held in single precision like binary STL, so both spellings load alike; a number
          // beyond a float's range (e.g. 1e39) is refused, as it would become infinite.
          if (!std::isfinite(static_cast<float>(*x))) {
            message = where + "vertex coordinate " + std::to_string(k + 1) +
                      " is outside the range of a 32-bit float (got " + quoted(t[k + 1]) +
                      ", expected at most 3.4e38 in magnitude)";
            return false;
          }
          v[k] = to_metres(static_cast<float>(*x), scale);
        }
        mesh.vertices.push_back(v);
        return true;
      }
      case State::kLoopDone:
        if (word != "endfacet") return expect("'endfacet'");
        state = State::kInSolid;
        return true;
    }
    return true;
  });
  if (message.empty() && state != State::kOutside) {
    message = name + ":" + std::to_string(last_line) +
              ": the file ends inside a solid (truncated? expected 'endsolid')";
  }
  if (!message.empty()) {
    set_error(error, message);
    return std::nullopt;
  }
  return mesh;
}

std::optional<std::string> read_file_bytes(const std::string& path, std::string* error) {
  std::string why;
  auto bytes = read_input_file(path, kMaxMeshFileBytes, "a mesh file (.obj or .stl)", &why);
  if (!bytes) set_error(error, path + ": " + why);
  return bytes;
}

std::string extension_of(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return lower(path.substr(dot + 1));
}

}  // namespace

double metres_per_unit(LengthUnit unit) { return unit == LengthUnit::kMillimetre ? 1e-3 : 1.0; }

std::optional<TriangleMesh> read_obj(std::string_view text, const std::string& name,
                                     LengthUnit unit, std::string* error) {
  if (!check_obj_statements(text, name, error)) return std::nullopt;
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(std::string(text), "", config)) {
    std::string why = reader.Error();
    while (!why.empty() && why.back() == '\n') why.pop_back();
    set_error(error, name + ": " + (why.empty() ? "cannot parse the OBJ file" : why));
    return std::nullopt;
  }
  const double scale = metres_per_unit(unit);
  const auto& v = reader.GetAttrib().vertices;
  TriangleMesh mesh;
  mesh.vertices.reserve(v.size() / 3);
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) {
    mesh.vertices.emplace_back(to_metres(v[i], scale), to_metres(v[i + 1], scale),
                               to_metres(v[i + 2], scale));
  }
  // The statements were checked above, but the reader splits lines and words its own way (a
  // bare carriage return ends a line for it, a form feed before "v" makes it no vertex): every
  // index it produced is checked against the vertices it read before any is used.
  const long vertex_count = static_cast<long>(mesh.vertices.size());
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const auto& idx = shape.mesh.indices;
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
      std::array<std::uint32_t, 3> triangle;
      for (int c = 0; c < 3; ++c) {
        const long v = idx[i + c].vertex_index;
        if (v < 0 || v >= vertex_count) {
          set_error(error, name + ": a face refers to vertex " + std::to_string(v + 1) +
                               ", but the OBJ reader found " + std::to_string(vertex_count) +
                               " vertices: a line was not read as the statement it looks "
                               "like (words are separated by spaces and tabs only, lines end "
                               "with a line feed)");
          return std::nullopt;
        }
        triangle[c] = static_cast<std::uint32_t>(v);
      }
      mesh.triangles.push_back(triangle);
    }
  }
  if (mesh.triangles.empty()) {
    set_error(error, name + ": no faces ('f' lines) in the OBJ file (expected a triangle mesh)");
    return std::nullopt;
  }
  mesh.weld_exact();
  return mesh;
}

std::optional<TriangleMesh> read_stl(std::string_view bytes, const std::string& name,
                                     LengthUnit unit, std::string* error) {
  const double scale = metres_per_unit(unit);
  std::optional<TriangleMesh> mesh;
  // Binary when the declared triangle count matches the size exactly (some binary files begin
  // their header with "solid", so the keyword alone does not decide).
  std::uint64_t declared = 0;
  if (bytes.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    declared = n;
  }
  const bool binary = bytes.size() >= 84 && bytes.size() == 84 + 50 * declared;
  const bool ascii = bytes.size() >= 5 && lower(std::string(bytes.substr(0, 5))) == "solid" &&
                     bytes.find('\0') == std::string_view::npos;
  if (binary) {
    mesh = read_binary_stl(bytes, name, scale, error);
  } else if (ascii) {
    mesh = read_ascii_stl(bytes, name, scale, error);
  } else if (bytes.size() >= 84) {
    set_error(error, name + ": not an STL file: binary header declares " + std::to_string(declared) +
                         " triangles (" + std::to_string(84 + 50 * declared) + " bytes) but the file has " +
                         std::to_string(bytes.size()) +
                         " bytes (truncated?), and it does not start with 'solid' (ASCII STL)");
    return std::nullopt;
  } else {
    set_error(error, name + ": not an STL file: " + std::to_string(bytes.size()) +
                         " bytes, shorter than a binary STL header (84 bytes) and not ASCII 'solid'");
    return std::nullopt;
  }
  if (!mesh) return std::nullopt;
  if (mesh->triangles.empty()) {
    set_error(error, name + ": the STL file holds no triangles");
    return std::nullopt;
  }
  mesh->weld_exact();
  return mesh;
}

std::optional<TriangleMesh> load_mesh_file(const std::string& path, LengthUnit unit,
                                           std::string* error) {
  const std::string ext = extension_of(path);
  if (ext != "obj" && ext != "stl") {
    set_error(error, path + ": unknown mesh file type (got extension '" + ext +
                         "', expected .obj or .stl)");
    return std::nullopt;
  }
  const auto bytes = read_file_bytes(path, error);
  if (!bytes) return std::nullopt;
  return ext == "obj" ? read_obj(*bytes, path, unit, error) : read_stl(*bytes, path, unit, error);
}

std::optional<TriangleMesh> load_closed_mesh_file(const std::string& path, LengthUnit unit,
                                                  std::string* error) {
  auto mesh = load_mesh_file(path, unit, error);
  if (!mesh) return std::nullopt;
  const MeshCheck check = check_closed_mesh(*mesh);
  if (!check.ok) {
    set_error(error, path + ": not a closed surface: " + check.error);
    return std::nullopt;
  }
  return mesh;
}

std::string mesh_file_bytes(const TriangleMesh& mesh, MeshFormat format, LengthUnit unit) {
  const double scale = metres_per_unit(unit);
  const char* unit_name = unit == LengthUnit::kMillimetre ? "mm" : "m";
  std::string out;
  char line[160];
  auto file_point = [&](std::uint32_t i) {
    const Vec3& v = mesh.vertices[i];
    return Eigen::Vector3f(to_file(v.x(), scale), to_file(v.y(), scale), to_file(v.z(), scale));
  };
  auto facet_normal = [&](const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                          const Eigen::Vector3f& c) {
    Eigen::Vector3f n = (b - a).cross(c - a);
    const float len = n.norm();
    return len > 0.0f ? Eigen::Vector3f(n / len) : Eigen::Vector3f::Zero();
  };

  if (format == MeshFormat::kObj) {
    out += std::string("# acdr triangle mesh, units: ") + unit_name + "\n";
    for (std::uint32_t i = 0; i < mesh.vertices.size(); ++i) {
      const Eigen::Vector3f p = file_point(i);
      // 9 significant digits give back the same float.
      std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
      out += line;
    }
    for (const auto& t : mesh.triangles) {
      std::snprintf(line, sizeof line, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
      out += line;
    }
  } else if (format == MeshFormat::kStlAscii) {
    out += "solid acdr\n";
    for (const auto& t : mesh.triangles) {
      const Eigen::Vector3f a = file_point(t[0]), b = file_point(t[1]), c = file_point(t[2]);
      const Eigen::Vector3f n = facet_normal(a, b, c);
      std::snprintf(line, sizeof line, "  facet normal %.9g %.9g %.9g\n    outer loop\n", n.x(),
                    n.y(), n.z());
      out += line;
      for (const Eigen::Vector3f* p : {&a, &b, &c}) {
        std::snprintf(line, sizeof line, "      vertex %.9g %.9g %.9g\n", p->x(), p->y(), p->z());
        out += line;
      }
      out += "    endloop\n  endfacet\n";
    }
    out += "endsolid acdr\n";
  } else {
    // 80-byte header that must not begin with "solid", the count, then 50 bytes per triangle.
    std::string header = std::string("acdr binary STL, units: ") + unit_name;
    header.resize(80, ' ');
    out += header;
    const auto n = static_cast<std::uint32_t>(mesh.triangles.size());
    out.append(reinterpret_cast<const char*>(&n), 4);
    for (const auto& t : mesh.triangles) {
      const Eigen::Vector3f a = file_point(t[0]), b = file_point(t[1]), c = file_point(t[2]);
      const Eigen::Vector3f nrm = facet_normal(a, b, c);
      for (const Eigen::Vector3f* p : {&nrm, &a, &b, &c}) {
        out.append(reinterpret_cast<const char*>(p->data()), 12);
      }
      out.append(2, '\0');  // attribute byte count
    }
  }
  return out;
}

bool save_mesh_file(const TriangleMesh& mesh, const std::string& path, MeshFormat format,
                    LengthUnit unit, std::string* error) {
  const std::string bytes = mesh_file_bytes(mesh, format, unit);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return set_error(error, path + ": cannot create the file");
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) return set_error(error, path + ": cannot write the file (disk full?)");
  return true;
}

}  // namespace acdr
