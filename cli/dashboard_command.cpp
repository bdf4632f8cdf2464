// `acdr dashboard`: open the record, select what the options ask for, then write the CSV, the
// picture, or open the window (ui/dashboard_window.hpp).
#include "cli/dashboard_command.hpp"

#include <ostream>

#include "db/outcome_side_file.hpp"
#include "ui/dashboard_model.hpp"
#include "ui/dashboard_window.hpp"
#include "ui/display.hpp"

namespace acdr {
namespace {

// The selection the options ask for; false with `error` when they name what is not there.
bool select(const DashboardModel& model, const DashboardOptions& o, DashboardSelection* sel,
            std::string* error) {
  *sel = default_selection(model);
  if (!o.trainee.empty()) {
    const DashboardTrainee* t = model.find_trainee(o.trainee);
    if (!t) {
      *error = "no trainee '" + o.trainee + "' in " + model.db_path;
      return false;
    }
    sel->trainee_id = o.trainee;
    sel->attempt_id = 0;
    for (auto it = t->attempts.rbegin(); it != t->attempts.rend(); ++it) {
      if (it->status == AttemptStatus::kCompleted) {
        sel->attempt_id = it->id;
        sel->module_id = it->module_id;
        break;
      }
    }
  }
  if (!o.module.empty()) {
    if (!model.find_module(o.module)) {
      *error = "no module '" + o.module + "' in " + model.db_path;
      return false;
    }
    sel->module_id = o.module;
  }
  if (o.attempt >= 0) sel->attempt_id = o.attempt;
  return true;
}

}  // namespace

int run_dashboard(const DashboardOptions& options, std::ostream& out, std::ostream& err) {
  const std::string path = options.db.empty() ? default_database_path() : options.db;
  // A reader: never create a record, never mark others' attempts.
  auto db = Database::open(path, OpenOptions{.create = false});
  if (!db) {
    err << db.error().message << "\n";
    return 2;  // missing, empty or another program's file: refused, as report and rescore do
  }
  // Finished attempts whose record could not be written are completed from their side files
  // (that marks nothing: it stores what their own program could not).
  for (const std::string& line : store_unsaved_outcomes(db.value()).notes)
    err << "note: " << line << "\n";
  auto model = load_dashboard(db.value());
  if (!model) {
    err << model.error().message << "\n";
    return 1;
  }
  DashboardSelection sel;
  std::string error;
  if (!select(model.value(), options, &sel, &error)) {
    err << error << "\n";
    return 2;
  }
  std::unique_ptr<AttemptDrillDown> attempt;
  if (sel.attempt_id > 0) {
    attempt = load_drill_down(db.value(), sel.attempt_id, &error);
    if (!attempt) {
      err << error << "\n";
      return 2;
    }
    sel.replay_t_s = options.replay_t_s >= 0 ? options.replay_t_s : attempt->opening_t_s();
  }

  if (!options.export_csv.empty()) {
    if (!write_dashboard_csv(model.value(), sel, attempt.get(), options.export_csv, &error)) {
      err << error << "\n";
      return 2;
    }
    out << "wrote " << options.export_csv << "\n";
    if (options.screenshot.empty()) return 0;
  }
  if (!options.screenshot.empty()) {
    if (!write_dashboard_png(model.value(), sel, attempt.get(), options.width, options.height,
                             options.screenshot, &error)) {
      err << error << "\n";
      return 2;
    }
    out << "wrote " << options.screenshot << "\n";
    return 0;
  }
  if (!display_available()) {
    err << "acdr dashboard needs a display for its window (or use --screenshot FILE)\n";
    return 2;
  }
  const DashboardWindowOptions window{options.width, options.height, options.export_dir};
  if (!run_dashboard_window(window, db.value(), std::move(model.value()), sel,
                            std::move(attempt), &error)) {
    err << error << "\n";
    return 2;
  }
  return 0;
}

}  // namespace acdr
