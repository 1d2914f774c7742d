#include "pipeline/app/results_ledger.h"

#include <sqlite3.h>

#include <cstdint>

#include "blocks/base/input_error.h"

namespace texsim {

namespace {

const char* kSchema = R"(CREATE TABLE IF NOT EXISTS runs (
  report_sha1 TEXT PRIMARY KEY,
  texsim_version TEXT, command TEXT,
  job INTEGER, scene TEXT, trace TEXT, overrides TEXT,
  fragments INTEGER, cycles INTEGER, cycles_per_fragment REAL,
  psnr_db REAL, nmse REAL, max_abs REAL, area_total REAL, time_us REAL,
  configuration TEXT))";

// A value at a JSON pointer, or null.
const nlohmann::ordered_json* at(const nlohmann::ordered_json& j, const char* ptr) {
  const nlohmann::ordered_json::json_pointer p(ptr);
  return j.contains(p) ? &j.at(p) : nullptr;
}

}  // namespace

ResultsLedger::ResultsLedger(const std::string& path) : path_(path) {
  if (sqlite3_open(path.c_str(), &db_) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw InputError(path, "cannot open the results ledger: " + why);
  }
  // Merges running at once into the same ledger wait for each other instead of failing with
  // "database is locked".
  sqlite3_busy_timeout(db_, kBusyTimeoutMs);
  exec(kSchema);
}

ResultsLedger::~ResultsLedger() { sqlite3_close(db_); }

void ResultsLedger::exec(const std::string& sql) const {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string why = err ? err : "unknown error";
    sqlite3_free(err);
    throw InputError(path_, "results ledger: " + why);
  }
}

bool ResultsLedger::add(const nlohmann::ordered_json& job, const nlohmann::ordered_json& report,
                        const std::string& report_sha1) {
  sqlite3_stmt* st = nullptr;
  const char* sql =
      "INSERT OR IGNORE INTO runs VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, "
      "?13, ?14, ?15, ?16)";
  if (sqlite3_prepare_v2(db_, sql, -1, &st, nullptr) != SQLITE_OK) {
    throw InputError(path_, std::string("results ledger: ") + sqlite3_errmsg(db_));
  }
  int col = 0;
  const auto text = [&](const std::string& s) {
    sqlite3_bind_text(st, ++col, s.c_str(), static_cast<int>(s.size()), SQLITE_TRANSIENT);
  };
  const auto value = [&](const nlohmann::ordered_json* v) {
    ++col;
    if (v == nullptr || v->is_null()) {
      sqlite3_bind_null(st, col);
    } else if (v->is_number_unsigned() && v->get<uint64_t>() > uint64_t{INT64_MAX}) {
      // Beyond SQLite's 64-bit signed integers: kept as REAL (its nearest double), never wrapped.
      sqlite3_bind_double(st, col, static_cast<double>(v->get<uint64_t>()));
    } else if (v->is_number_integer()) {
      sqlite3_bind_int64(st, col, v->get<int64_t>());
    } else if (v->is_number()) {
      sqlite3_bind_double(st, col, v->get<double>());
    } else {
      const std::string s = v->is_string() ? v->get<std::string>() : v->dump();
      sqlite3_bind_text(st, col, s.c_str(), static_cast<int>(s.size()), SQLITE_TRANSIENT);
    }
  };
  text(report_sha1);
  value(at(report, "/provenance/texsim_version"));
  value(at(report, "/provenance/command"));
  for (const char* k : {"/job", "/scene", "/trace", "/overrides"}) value(at(job, k));
  for (const char* k : {"/fragments", "/cycles", "/cycles_per_fragment", "/accuracy/psnr_db",
                        "/accuracy/nmse", "/accuracy/max_abs", "/area_total", "/physical/time_us"})
    value(at(report, k));
  nlohmann::ordered_json config;
  if (const auto* p = at(report, "/provenance/pipeline")) config["pipeline"] = *p;
  if (const auto* t = at(report, "/provenance/tech")) config["tech"] = *t;
  text(config.dump());
  const int rc = sqlite3_step(st);
  sqlite3_finalize(st);
  if (rc != SQLITE_DONE)
    throw InputError(path_, std::string("results ledger: ") + sqlite3_errmsg(db_));
  return sqlite3_changes(db_) > 0;
}

int64_t ResultsLedger::rows() const {
  sqlite3_stmt* st = nullptr;
  int64_t n = 0;
  if (sqlite3_prepare_v2(db_, "SELECT COUNT(*) FROM runs", -1, &st, nullptr) == SQLITE_OK &&
      sqlite3_step(st) == SQLITE_ROW)
    n = sqlite3_column_int64(st, 0);
  sqlite3_finalize(st);
  return n;
}

}  // namespace texsim
