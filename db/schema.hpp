// The record's schema and its ordered migrations. The version lives in PRAGMA user_version;
// each migration moves the file from version-1 to version inside the open transaction, and a
// file newer than kSchemaVersion is refused (SQLite's own file-format stance: never guess at a
// format you do not know).
#pragma once

#include <cstdint>
#include <span>

#include "db/db_result.hpp"

namespace acdr {

class Database;

/// The schema version this program writes and understands.
inline constexpr int kSchemaVersion = 4;

/// PRAGMA application_id of an ACDR record: "ACDR" in ASCII. Lets us refuse another program's
/// SQLite file instead of adding our tables to it.
inline constexpr std::int32_t kApplicationId = 0x41434452;

struct Migration {
  int version;              ///< user_version after this migration
  const char* description;  ///< one line, for logs and errors
  const char* sql;          ///< constant DDL/DML, run as one script
};

/// All migrations, ordered by version 1..kSchemaVersion.
std::span<const Migration> schema_migrations();

/// Brings `db` to kSchemaVersion inside one IMMEDIATE transaction (so two processes opening a
/// new file at once do not both migrate). Refuses a newer or foreign file.
DbStatus migrate_schema(Database& db);

/// Checks, without writing, that `db` is an ACDR record at exactly kSchemaVersion (read-only
/// opens).
DbStatus check_schema_current(Database& db);

/// Decides, without writing, whether the file behind `db` (a read-only connection) may be
/// opened as the record: an ACDR record at a version this program knows, or, when
/// `may_initialise`, an SQLite file with no tables and no stamp (a new record). Refuses a file
/// with another application id, a newer version, tables of its own, or (when not
/// `may_initialise`) nothing in it yet. Database::open calls it before any pragma that writes,
/// so a refused file is left byte for byte as it was.
DbStatus check_record_identity(Database& db, bool may_initialise);

}  // namespace acdr
