// libFuzzer target: the OBJ mesh reader on any bytes (what it must hold: mesh_reader_check.hpp).
#include <cstddef>
#include <cstdint>

#include "engine/geometry/mesh_io.hpp"
#include "tests/fuzz/mesh_reader_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return acdr::fuzz::check_mesh_reader(acdr::read_obj, "fuzz.obj", data, size);
}
