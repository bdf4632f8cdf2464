// Formats of a benchmark report: the readable table, CSV, and JSON with the keys
// docs/performance.md lists ({"points": [{"scene", "solver", "settings", "wall_s_per_sim_s", "force_rms_error",
// "removed_error", ...}], "scaling": {...}, "skips": [...]}).
#pragma once

#include <nlohmann/json.hpp>

#include <ostream>

#include "bench/bench_suite.hpp"

namespace acdr {

/// The tables (work-precision points, scaling with its fit, skips) as aligned text.
void write_bench_table(const BenchReport& report, std::ostream& out);

/// Every figure as CSV, one row per point, scaling lattice and skip side (column `kind`).
void write_bench_csv(const BenchReport& report, std::ostream& out);

/// The report as JSON.
nlohmann::json bench_report_json(const BenchReport& report);

}  // namespace acdr
