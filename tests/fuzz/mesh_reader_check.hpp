// What the mesh fuzz targets check of a reader on any bytes: a refusal names the file, and a
// mesh it accepts has finite vertices and triangles whose indices name existing vertices. A
// broken promise aborts, which libFuzzer reports with the input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "engine/geometry/mesh_io.hpp"

namespace acdr::fuzz {

template <typename Reader>
int check_mesh_reader(Reader read, const std::string& name, const std::uint8_t* data,
                      std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::string error;
  const auto mesh = read(bytes, name, LengthUnit::kMillimetre, &error);
  if (!mesh) {
    if (error.rfind(name, 0) != 0) std::abort();
    return 0;
  }
  for (const Vec3& v : mesh->vertices) {
    if (!v.allFinite()) std::abort();
  }
  for (const auto& t : mesh->triangles) {
    for (int k = 0; k < 3; ++k) {
      if (t[k] >= mesh->vertices.size()) std::abort();
    }
  }
  return 0;
}

}  // namespace acdr::fuzz
