#pragma once
// A results ledger in SQLite: one row per run report merged into it, keyed by the report's
// SHA-1 so merging the same job twice adds nothing. It keeps what reproduces a run (version,
// command, scene, trace, overrides, resolved configuration as JSON) beside its figures, so
// results of many sweeps can be queried together (docs/sweeps.md gives the schema).
#include <nlohmann/json.hpp>
#include <string>

struct sqlite3;

namespace texsim {

class ResultsLedger {
 public:
  // How long a statement waits for another connection's lock before failing.
  static constexpr int kBusyTimeoutMs = 10000;

  // Opens (creating if needed) the database and its table; throws InputError naming the file.
  explicit ResultsLedger(const std::string& path);
  ~ResultsLedger();
  ResultsLedger(const ResultsLedger&) = delete;
  ResultsLedger& operator=(const ResultsLedger&) = delete;

  // Adds a run; returns false if a report with the same SHA-1 is already there. Integers beyond
  // the range of int64 (SQLite's INTEGER) are stored as REAL.
  bool add(const nlohmann::ordered_json& job, const nlohmann::ordered_json& report,
           const std::string& report_sha1);
  int64_t rows() const;

 private:
  void exec(const std::string& sql) const;
  std::string path_;
  sqlite3* db_ = nullptr;
};

}  // namespace texsim
