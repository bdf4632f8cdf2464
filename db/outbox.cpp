// The outbox of xAPI statements: see outbox.hpp.
#include "db/outbox.hpp"

#include <map>

#include "db/attempt_store.hpp"
#include "db/catalog.hpp"
#include "db/utc_time.hpp"

namespace acdr {

namespace {

constexpr const char* kItemColumns =
    "id, statement_id, attempt_id, statement, queued_utc, state, tries, last_try_utc, "
    "last_error, sent_utc, sent_to";

OutboxState parse_state(const std::string& text) {
  if (text == "sent") return OutboxState::kSent;
  if (text == "failed") return OutboxState::kFailed;
  return OutboxState::kQueued;
}

OutboxItem read_item(const Statement& s) {
  OutboxItem item;
  item.id = s.column_int64(0);
  item.statement_id = s.column_text(1);
  item.attempt_id = s.column_int64(2);
  item.statement = s.column_text(3);
  item.queued_utc = s.column_text(4);
  item.state = parse_state(s.column_text(5));
  item.tries = static_cast<int>(s.column_int64(6));
  item.last_try_utc = s.column_optional_text(7);
  item.last_error = s.column_text(8);
  item.sent_utc = s.column_optional_text(9);
  item.sent_to = s.column_text(10);
  return item;
}

// Inserts the statements, skipping ids already queued; returns how many were new.
DbResult<int> insert_statements(Database& db, const std::vector<XapiStatement>& statements,
                                const std::map<std::string, std::int64_t>& attempt_ids) {
  DbResult<Statement> s = db.prepare(
      "INSERT INTO xapi_outbox (statement_id, attempt_id, statement, queued_utc) "
      "VALUES (?, ?, ?, ?) ON CONFLICT (statement_id) DO NOTHING");
  if (!s) return s.error();
  const std::string now = utc_now_text();
  int added = 0;
  for (const XapiStatement& st : statements) {
    const auto attempt = attempt_ids.find(st.attempt_uuid);
    if (attempt == attempt_ids.end()) continue;
    if (DbStatus b = s->bind_all(st.id, attempt->second, st.json, now); !b) return b.error();
    if (DbStatus r = s->run(); !r) {
      return DbError{db.path() + ": queueing xAPI statement " + st.id + " of attempt " +
                         std::to_string(attempt->second) + ": " + r.error().message,
                     r.error().sqlite_code};
    }
    added += db.changes();
    if (DbStatus r = s->reset(); !r) return r.error();
  }
  return added;
}

DbResult<std::map<std::string, ModuleRecord>> modules_by_id(Database& db) {
  DbResult<std::vector<ModuleRecord>> modules = list_modules(db);
  if (!modules) return modules.error();
  std::map<std::string, ModuleRecord> out;
  for (ModuleRecord& m : modules.value()) out.emplace(m.id, std::move(m));
  return out;
}

DbStatus update_item(Database& db, const char* sql, std::int64_t id, const std::string& a,
                     const std::string& b) {
  DbResult<Statement> s = db.prepare(sql);
  if (!s) return s.error();
  if (DbStatus bound = s->bind_all(a, b, id); !bound) return bound;
  if (DbStatus r = s->run(); !r) return r;
  if (db.changes() != 1) {
    return DbError{db.path() + ": no queued xAPI statement with outbox id " + std::to_string(id),
                   0};
  }
  return {};
}

}  // namespace

const char* outbox_state_name(OutboxState state) {
  switch (state) {
    case OutboxState::kQueued:
      return "queued";
    case OutboxState::kSent:
      return "sent";
    case OutboxState::kFailed:
      return "failed";
  }
  return "queued";
}

DbResult<int> queue_attempt_statements(Database& db, std::int64_t attempt_id,
                                       const XapiOptions& options) {
  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();
  DbResult<std::optional<AttemptRecord>> attempt =
      load_attempt(db, attempt_id, AttemptDetail{false, false, false});
  if (!attempt) return attempt.error();
  if (!attempt.value()) {
    return DbError{db.path() + ": no attempt with id " + std::to_string(attempt_id), 0};
  }
  const AttemptRecord& a = **attempt;
  if (a.is_practice() || a.status != AttemptStatus::kCompleted) return 0;

  // Which statements an attempt gets depends on the attempts before it in its registration (a
  // registration has one `passed`), so the export is built over the registration and this
  // attempt's statements are taken from it.
  AttemptFilter filter;
  filter.trainee_id = a.trainee_id;
  filter.module_id = a.module_id;
  filter.include_practice = false;
  DbResult<std::vector<AttemptRecord>> all =
      list_attempts(db, filter, AttemptDetail{true, false, false});
  if (!all) return all.error();
  std::vector<AttemptRecord> registration;
  for (AttemptRecord& r : all.value()) {
    if (r.registration == a.registration) registration.push_back(std::move(r));
  }
  DbResult<std::map<std::string, ModuleRecord>> modules = modules_by_id(db);
  if (!modules) return modules.error();
  DbResult<int> added = insert_statements(
      db, xapi_statements(registration, modules.value(), options), {{a.uuid, a.id}});
  if (!added) return added;
  if (DbStatus c = tx->commit(); !c) return c.error();
  return added;
}

DbResult<int> queue_all_statements(Database& db, const XapiOptions& options) {
  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();
  AttemptFilter filter;
  filter.include_practice = false;
  DbResult<std::vector<AttemptRecord>> all =
      list_attempts(db, filter, AttemptDetail{true, false, false});
  if (!all) return all.error();
  std::map<std::string, std::int64_t> ids;
  for (const AttemptRecord& a : all.value()) ids.emplace(a.uuid, a.id);
  DbResult<std::map<std::string, ModuleRecord>> modules = modules_by_id(db);
  if (!modules) return modules.error();
  DbResult<int> added =
      insert_statements(db, xapi_statements(all.value(), modules.value(), options), ids);
  if (!added) return added;
  if (DbStatus c = tx->commit(); !c) return c.error();
  return added;
}

DbResult<std::vector<OutboxItem>> queued_statements(Database& db, int limit) {
  DbResult<Statement> s = db.prepare(std::string("SELECT ") + kItemColumns +
                                     " FROM xapi_outbox WHERE state = 'queued' ORDER BY id "
                                     "LIMIT ?");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(limit); !b) return b.error();
  std::vector<OutboxItem> items;
  if (DbStatus r = s->for_each_row([&] { items.push_back(read_item(*s)); }); !r) {
    return r.error();
  }
  return items;
}

DbResult<std::vector<OutboxItem>> list_outbox(Database& db, std::optional<OutboxState> state) {
  DbResult<Statement> s = db.prepare(std::string("SELECT ") + kItemColumns +
                                     " FROM xapi_outbox WHERE ?1 IS NULL OR state = ?1 "
                                     "ORDER BY id");
  if (!s) return s.error();
  const std::optional<std::string> wanted =
      state ? std::optional<std::string>(outbox_state_name(*state)) : std::nullopt;
  if (DbStatus b = s->bind_all(wanted); !b) return b.error();
  std::vector<OutboxItem> items;
  if (DbStatus r = s->for_each_row([&] { items.push_back(read_item(*s)); }); !r) {
    return r.error();
  }
  return items;
}

DbStatus mark_statement_sent(Database& db, std::int64_t id, const std::string& endpoint,
                             const std::string& note) {
  const std::string now = utc_now_text();
  DbResult<Statement> s = db.prepare(
      "UPDATE xapi_outbox SET state = 'sent', tries = tries + 1, last_try_utc = ?1, "
      "sent_utc = ?1, sent_to = ?2, last_error = ?3 WHERE id = ?4 AND state = 'queued'");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(now, endpoint, note, id); !b) return b;
  if (DbStatus r = s->run(); !r) return r;
  if (db.changes() == 1) return {};
  // Not queued any more: fine when another sender got there first.
  DbResult<Statement> check = db.prepare("SELECT state FROM xapi_outbox WHERE id = ?");
  if (!check) return check.error();
  if (DbStatus b = check->bind_all(id); !b) return b;
  DbResult<bool> row = check->step();
  if (!row) return row.error();
  if (row.value() && check->column_text(0) == "sent") return {};
  return DbError{db.path() + ": no queued xAPI statement with outbox id " + std::to_string(id), 0};
}

DbStatus mark_statement_failed(Database& db, std::int64_t id, const std::string& error) {
  return update_item(db,
                     "UPDATE xapi_outbox SET state = 'failed', tries = tries + 1, "
                     "last_try_utc = ?1, last_error = ?2 WHERE id = ?3 AND state = 'queued'",
                     id, utc_now_text(), error);
}

DbStatus note_statement_try(Database& db, std::int64_t id, const std::string& error) {
  return update_item(db,
                     "UPDATE xapi_outbox SET tries = tries + 1, last_try_utc = ?1, "
                     "last_error = ?2 WHERE id = ?3 AND state = 'queued'",
                     id, utc_now_text(), error);
}

DbResult<int> requeue_failed_statements(Database& db) {
  if (DbStatus r = db.exec("UPDATE xapi_outbox SET state = 'queued' WHERE state = 'failed'"); !r) {
    return r.error();
  }
  return db.changes();
}

DbResult<OutboxCounts> outbox_counts(Database& db) {
  DbResult<Statement> s = db.prepare(
      "SELECT count(*) FILTER (WHERE state = 'queued'), count(*) FILTER (WHERE state = 'sent'), "
      "count(*) FILTER (WHERE state = 'failed') FROM xapi_outbox");
  if (!s) return s.error();
  DbResult<bool> row = s->step();
  if (!row) return row.error();
  return OutboxCounts{s->column_int64(0), s->column_int64(1), s->column_int64(2)};
}

}  // namespace acdr
