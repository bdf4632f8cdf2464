// The catalogue of the record: trainees, curricula and modules (who trains, and on what).
// Registering is idempotent, so a program can register the modules it loads on every run.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "db/database.hpp"
#include "db/records.hpp"

namespace acdr {

/// Inserts the trainee, or updates its display name (an empty name keeps the stored one). The
/// creation time is kept from the first insert.
DbStatus upsert_trainee(Database& db, const TraineeRecord& trainee);
DbResult<std::optional<TraineeRecord>> find_trainee(Database& db, const std::string& id);
/// All trainees ordered by id.
DbResult<std::vector<TraineeRecord>> list_trainees(Database& db);

DbStatus upsert_curriculum(Database& db, const CurriculumRecord& curriculum);
DbResult<std::vector<CurriculumRecord>> list_curricula(Database& db);

/// Inserts or updates the module and its prerequisites in one transaction and returns it as
/// stored: `version` is 1 for a new module and goes up by one when the scenario hash differs
/// from the stored one. The curriculum, when given, must exist. consecutive_passes_required
/// must be >= 1 and pass_score finite.
DbResult<ModuleRecord> upsert_module(Database& db, const ModuleRecord& module);
DbResult<std::optional<ModuleRecord>> find_module(Database& db, const std::string& id);
/// All modules, ordered by curriculum, position, id; only those of `curriculum_id` when given.
DbResult<std::vector<ModuleRecord>> list_modules(
    Database& db, const std::optional<std::string>& curriculum_id = std::nullopt);

/// The module ids that must be mastered before `module` is unlocked: its explicit list, or the
/// module(s) at the highest position below its own in the same curriculum.
DbResult<std::vector<std::string>> effective_prerequisites(Database& db,
                                                           const ModuleRecord& module);

}  // namespace acdr
