// libFuzzer target: the STL mesh reader on any bytes. A mesh it accepts has finite
// vertices and triangles whose indices name existing vertices.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "engine/geometry/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  std::string error;
  const auto mesh = acdr::read_stl(bytes, "fuzz.stl", acdr::LengthUnit::kMillimetre, &error);
  if (!mesh) {
    if (error.rfind("fuzz.stl", 0) != 0) std::abort();
    return 0;
  }
  for (const acdr::Vec3& v : mesh->vertices) {
    if (!v.allFinite()) std::abort();
  }
  for (const auto& t : mesh->triangles) {
    for (int k = 0; k < 3; ++k) {
      if (t[k] >= mesh->vertices.size()) std::abort();
    }
  }
  return 0;
}
