// Trainees, curricula and modules: see catalog.hpp.
#include "db/catalog.hpp"

#include <cmath>

#include "db/utc_time.hpp"

namespace acdr {

namespace {

constexpr const char* kModuleColumns =
    "id, curriculum_id, position, title, scenario_path, scenario_hash, version, "
    "explicit_prerequisites, consecutive_passes, pass_score";

ModuleRecord read_module_row(const Statement& s) {
  ModuleRecord m;
  m.id = s.column_text(0);
  m.curriculum_id = s.column_optional_text(1);
  m.position = static_cast<int>(s.column_int64(2));
  m.title = s.column_text(3);
  m.scenario_path = s.column_text(4);
  m.scenario_hash = s.column_text(5);
  m.version = static_cast<int>(s.column_int64(6));
  if (s.column_int64(7) != 0) m.prerequisites.emplace();
  m.consecutive_passes_required = static_cast<int>(s.column_int64(8));
  m.pass_score = s.column_double(9);
  return m;
}

// Fills the explicit prerequisite list of modules that have one.
DbStatus load_prerequisites(Database& db, ModuleRecord& m) {
  if (!m.prerequisites) return {};
  DbResult<Statement> s = db.prepare(
      "SELECT prerequisite_id FROM module_prerequisites WHERE module_id = ? "
      "ORDER BY prerequisite_id");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(m.id); !b) return b;
  if (DbStatus r = s->for_each_row([&] { m.prerequisites->push_back(s->column_text(0)); }); !r) {
    return r.error();
  }
  return {};
}

DbResult<bool> row_exists(Database& db, const char* sql, const std::string& key) {
  DbResult<Statement> s = db.prepare(sql);
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(key); !b) return b.error();
  return s->step();
}

}  // namespace

DbStatus upsert_trainee(Database& db, const TraineeRecord& trainee) {
  if (trainee.id.empty()) return DbError{db.path() + ": trainee id is empty (expected an id)", 0};
  DbResult<Statement> s = db.prepare(
      "INSERT INTO trainees (id, display_name, created_utc) VALUES (?, ?, ?) "
      "ON CONFLICT (id) DO UPDATE SET display_name = excluded.display_name "
      "WHERE excluded.display_name <> ''");
  if (!s) return s.error();
  const std::string created =
      trainee.created_utc.empty() ? utc_now_text() : trainee.created_utc;
  if (DbStatus b = s->bind_all(trainee.id, trainee.display_name, created); !b) return b;
  return s->run();
}

DbResult<std::optional<TraineeRecord>> find_trainee(Database& db, const std::string& id) {
  DbResult<Statement> s =
      db.prepare("SELECT id, display_name, created_utc FROM trainees WHERE id = ?");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(id); !b) return b.error();
  DbResult<bool> row = s->step();
  if (!row) return row.error();
  if (!row.value()) return std::optional<TraineeRecord>();
  return std::optional<TraineeRecord>(
      TraineeRecord{s->column_text(0), s->column_text(1), s->column_text(2)});
}

DbResult<std::vector<TraineeRecord>> list_trainees(Database& db) {
  DbResult<Statement> s =
      db.prepare("SELECT id, display_name, created_utc FROM trainees ORDER BY id");
  if (!s) return s.error();
  std::vector<TraineeRecord> out;
  if (DbStatus r = s->for_each_row([&] {
        out.push_back(TraineeRecord{s->column_text(0), s->column_text(1), s->column_text(2)});
      });
      !r) {
    return r.error();
  }
  return out;
}

DbStatus upsert_curriculum(Database& db, const CurriculumRecord& curriculum) {
  if (curriculum.id.empty()) {
    return DbError{db.path() + ": curriculum id is empty (expected an id)", 0};
  }
  DbResult<Statement> s = db.prepare(
      "INSERT INTO curricula (id, title) VALUES (?, ?) "
      "ON CONFLICT (id) DO UPDATE SET title = excluded.title");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(curriculum.id, curriculum.title); !b) return b;
  return s->run();
}

DbResult<std::vector<CurriculumRecord>> list_curricula(Database& db) {
  DbResult<Statement> s = db.prepare("SELECT id, title FROM curricula ORDER BY id");
  if (!s) return s.error();
  std::vector<CurriculumRecord> out;
  if (DbStatus r = s->for_each_row([&] {
        out.push_back(CurriculumRecord{s->column_text(0), s->column_text(1)});
      });
      !r) {
    return r.error();
  }
  return out;
}

DbResult<ModuleRecord> upsert_module(Database& db, const ModuleRecord& module) {
  // Check the input first so the error names the module and the value.
  const std::string where = db.path() + ": module '" + module.id + "': ";
  if (module.id.empty()) return DbError{db.path() + ": module id is empty (expected an id)", 0};
  if (module.consecutive_passes_required < 1) {
    return DbError{where + "consecutive_passes_required is " +
                       std::to_string(module.consecutive_passes_required) + " (expected >= 1)",
                   0};
  }
  if (!std::isfinite(module.pass_score)) {
    return DbError{where + "pass_score is not a finite number (expected 0..100)", 0};
  }
  if (module.prerequisites) {
    for (const std::string& p : *module.prerequisites) {
      if (p.empty() || p == module.id) {
        return DbError{where + "prerequisite '" + p +
                           "' is invalid (expected another module's id)",
                       0};
      }
    }
  }

  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();

  if (module.curriculum_id) {
    DbResult<bool> found =
        row_exists(db, "SELECT 1 FROM curricula WHERE id = ?", *module.curriculum_id);
    if (!found) return found.error();
    if (!found.value()) {
      return DbError{where + "curriculum '" + *module.curriculum_id +
                         "' is not registered (call upsert_curriculum first)",
                     0};
    }
  }

  // The version follows the scenario file: same hash, same version.
  int version = 1;
  {
    DbResult<Statement> s = db.prepare("SELECT version, scenario_hash FROM modules WHERE id = ?");
    if (!s) return s.error();
    if (DbStatus b = s->bind_all(module.id); !b) return b.error();
    DbResult<bool> row = s->step();
    if (!row) return row.error();
    if (row.value()) {
      version = static_cast<int>(s->column_int64(0));
      if (s->column_text(1) != module.scenario_hash) ++version;
    }
  }

  {
    DbResult<Statement> s = db.prepare(
        "INSERT INTO modules (id, curriculum_id, position, title, scenario_path, scenario_hash, "
        "version, explicit_prerequisites, consecutive_passes, pass_score) "
        "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?) "
        "ON CONFLICT (id) DO UPDATE SET curriculum_id = excluded.curriculum_id, "
        "position = excluded.position, title = excluded.title, "
        "scenario_path = excluded.scenario_path, scenario_hash = excluded.scenario_hash, "
        "version = excluded.version, explicit_prerequisites = excluded.explicit_prerequisites, "
        "consecutive_passes = excluded.consecutive_passes, pass_score = excluded.pass_score");
    if (!s) return s.error();
    if (DbStatus b = s->bind_all(module.id, module.curriculum_id, module.position, module.title,
                                 module.scenario_path, module.scenario_hash, version,
                                 module.prerequisites.has_value(),
                                 module.consecutive_passes_required, module.pass_score);
        !b) {
      return b.error();
    }
    if (DbStatus r = s->run(); !r) return r.error();
  }

  {
    DbResult<Statement> del = db.prepare("DELETE FROM module_prerequisites WHERE module_id = ?");
    if (!del) return del.error();
    if (DbStatus b = del->bind_all(module.id); !b) return b.error();
    if (DbStatus r = del->run(); !r) return r.error();
  }
  if (module.prerequisites) {
    DbResult<Statement> ins = db.prepare(
        "INSERT OR IGNORE INTO module_prerequisites (module_id, prerequisite_id) VALUES (?, ?)");
    if (!ins) return ins.error();
    for (const std::string& p : *module.prerequisites) {
      if (DbStatus b = ins->bind_all(module.id, p); !b) return b.error();
      if (DbStatus r = ins->run(); !r) return r.error();
      if (DbStatus r = ins->reset(); !r) return r.error();
    }
  }

  if (DbStatus c = tx->commit(); !c) return c.error();
  DbResult<std::optional<ModuleRecord>> stored = find_module(db, module.id);
  if (!stored) return stored.error();
  if (!stored.value()) return DbError{where + "vanished after being stored", 0};
  return std::move(*stored.value());
}

DbResult<std::optional<ModuleRecord>> find_module(Database& db, const std::string& id) {
  DbResult<Statement> s =
      db.prepare(std::string("SELECT ") + kModuleColumns + " FROM modules WHERE id = ?");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(id); !b) return b.error();
  DbResult<bool> row = s->step();
  if (!row) return row.error();
  if (!row.value()) return std::optional<ModuleRecord>();
  ModuleRecord m = read_module_row(*s);
  if (DbStatus p = load_prerequisites(db, m); !p) return p.error();
  return std::optional<ModuleRecord>(std::move(m));
}

DbResult<std::vector<ModuleRecord>> list_modules(Database& db,
                                                 const std::optional<std::string>& curriculum_id) {
  DbResult<Statement> s = db.prepare(
      std::string("SELECT ") + kModuleColumns +
      " FROM modules WHERE (?1 IS NULL OR curriculum_id = ?1) "
      "ORDER BY curriculum_id IS NULL, curriculum_id, position, id");
  if (!s) return s.error();
  if (DbStatus b = s->bind(1, curriculum_id); !b) return b.error();
  std::vector<ModuleRecord> out;
  if (DbStatus r = s->for_each_row([&] { out.push_back(read_module_row(*s)); }); !r) {
    return r.error();
  }
  for (ModuleRecord& m : out) {
    if (DbStatus p = load_prerequisites(db, m); !p) return p.error();
  }
  return out;
}

DbResult<std::vector<std::string>> effective_prerequisites(Database& db,
                                                           const ModuleRecord& module) {
  if (module.prerequisites) return *module.prerequisites;
  std::vector<std::string> out;
  if (!module.curriculum_id) return out;
  // "Passing unlocks the next module": the module(s) at the nearest lower position.
  DbResult<Statement> s = db.prepare(
      "SELECT id FROM modules WHERE curriculum_id = ?1 AND id <> ?2 AND position = "
      "(SELECT max(position) FROM modules WHERE curriculum_id = ?1 AND position < ?3) "
      "ORDER BY id");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(*module.curriculum_id, module.id, module.position); !b) {
    return b.error();
  }
  if (DbStatus r = s->for_each_row([&] { out.push_back(s->column_text(0)); }); !r) {
    return r.error();
  }
  return out;
}

}  // namespace acdr
