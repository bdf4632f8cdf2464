// Loading a curriculum's modules from a folder: see curriculum_set.hpp.
#include "scenarios/curriculum_set.hpp"

#include <algorithm>
#include <filesystem>
#include <set>
#include <system_error>

#include "scenarios/scenario_loader.hpp"

namespace acdr {

CurriculumSet load_curriculum_set(const std::string& directory, const std::string& curriculum_id) {
  namespace fs = std::filesystem;
  CurriculumSet set;
  std::error_code ec;
  std::vector<fs::path> files;
  for (fs::directory_iterator it(directory.empty() ? "." : directory, ec), end; !ec && it != end;
       it.increment(ec)) {
    if (it->path().extension() == ".json" && it->is_regular_file(ec)) files.push_back(it->path());
  }
  if (ec) {
    set.skipped.push_back(directory + ": cannot list the folder (" + ec.message() + ")");
    return set;
  }
  std::sort(files.begin(), files.end());
  std::set<std::string> ids;
  for (const fs::path& file : files) {
    const LoadResult loaded = load_scenario_file(file.string());
    if (!loaded.ok()) {
      set.skipped.push_back(file.string() + ": not a valid scenario (" +
                            std::to_string(loaded.errors.size()) + " error" +
                            (loaded.errors.size() == 1 ? "" : "s") + "; acdr validate " +
                            file.string() + " lists them)");
      continue;
    }
    if (loaded.model->curriculum != curriculum_id) continue;
    if (!ids.insert(loaded.model->id).second) {
      set.skipped.push_back(file.string() + ": module id '" + loaded.model->id +
                            "' is already taken by another file of the folder");
      continue;
    }
    set.modules.push_back(loaded.model);
  }
  std::stable_sort(set.modules.begin(), set.modules.end(),
                   [](const auto& a, const auto& b) { return a->module_order < b->module_order; });
  return set;
}

}  // namespace acdr
