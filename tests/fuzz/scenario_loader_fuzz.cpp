// libFuzzer target: the scenario loader on any bytes. It must return (never crash, hang or
// trip a sanitizer) with either a model or errors, each naming the file, a line within the
// text and a JSON path.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "scenarios/scenario_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const acdr::LoadResult r = acdr::load_scenario_text(text, "fuzz.json");
  if (r.ok() == !r.errors.empty()) std::abort();
  int lines = 1;
  for (char c : text) lines += c == '\n' ? 1 : 0;
  for (const acdr::ScenarioError& e : r.errors) {
    if (e.file != "fuzz.json" || e.line < 0 || e.line > lines || e.message.empty()) std::abort();
    if (!e.json_path.empty() && e.json_path[0] != '/') std::abort();
  }
  return 0;
}
