#include "reports/results_store.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/error.hpp"

namespace statebench::reports {
namespace {

constexpr const char* kSchema = R"sql(
CREATE TABLE IF NOT EXISTS sweeps (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  name TEXT NOT NULL, file TEXT, definition TEXT, code_version TEXT, host TEXT, shard TEXT,
  started_at TEXT);
CREATE TABLE IF NOT EXISTS runs (
  id TEXT PRIMARY KEY, sweep TEXT, scenario TEXT, seed INTEGER, parameters TEXT,
  code_version TEXT, status TEXT NOT NULL, exit_code INTEGER, error TEXT, wall_s REAL,
  cpu_s REAL, host TEXT, finished_at TEXT, run_dir TEXT, cache TEXT);
CREATE TABLE IF NOT EXISTS run_parameters (
  run_id TEXT NOT NULL REFERENCES runs(id) ON DELETE CASCADE, axis TEXT NOT NULL,
  value TEXT, PRIMARY KEY (run_id, axis));
CREATE TABLE IF NOT EXISTS metrics (
  run_id TEXT NOT NULL REFERENCES runs(id) ON DELETE CASCADE, estimator TEXT NOT NULL,
  name TEXT NOT NULL, value REAL, PRIMARY KEY (run_id, estimator, name));
CREATE TABLE IF NOT EXISTS artifacts (
  run_id TEXT NOT NULL REFERENCES runs(id) ON DELETE CASCADE, estimator TEXT NOT NULL,
  kind TEXT NOT NULL, path TEXT, PRIMARY KEY (run_id, estimator, kind));
CREATE INDEX IF NOT EXISTS metrics_by_name ON metrics(name, estimator);
)sql";

}  // namespace

struct ResultsStore::Db {
  sqlite3* handle = nullptr;
  std::string file;

  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(file + ": " + what + ": " + sqlite3_errmsg(handle));
  }
  // The first column of the first row of a query returning one integer.
  std::int64_t Integer(const char* sql) const {
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(handle, sql, -1, &stmt, nullptr) != SQLITE_OK) Fail("cannot read");
    const int rc = sqlite3_step(stmt);
    const std::int64_t value = rc == SQLITE_ROW ? sqlite3_column_int64(stmt, 0) : 0;
    sqlite3_finalize(stmt);
    if (rc != SQLITE_ROW && rc != SQLITE_DONE) Fail("cannot read");
    return value;
  }
  void Exec(const std::string& sql) const {
    char* message = nullptr;
    if (sqlite3_exec(handle, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
      const std::string text = message ? message : "unknown error";
      sqlite3_free(message);
      throw InputError(file + ": " + text);
    }
  }
};

namespace {

// A prepared statement; Bind* by 1-based index, Step() until it returns false.
class Statement {
 public:
  Statement(const ResultsStore* owner, sqlite3* db, const std::string& file, const char* sql)
      : db_(db), file_(file) {
    (void)owner;
    if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK) Fail("prepare");
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& Bind(int i, const std::string& v) {
    sqlite3_bind_text(stmt_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Statement& Bind(int i, double v) {
    if (std::isfinite(v)) {
      sqlite3_bind_double(stmt_, i, v);
    } else {
      sqlite3_bind_null(stmt_, i);  // SQLite has no NaN; a missing figure reads back as NaN
    }
    return *this;
  }
  Statement& Bind(int i, std::int64_t v) {
    sqlite3_bind_int64(stmt_, i, v);
    return *this;
  }
  bool Step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    Fail("step");
  }
  void Run() {
    Step();
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  std::string Text(int col) const {
    const auto* t = sqlite3_column_text(stmt_, col);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
  double Real(int col) const {
    return sqlite3_column_type(stmt_, col) == SQLITE_NULL ? std::nan("")
                                                          : sqlite3_column_double(stmt_, col);
  }
  std::int64_t Int(int col) const { return sqlite3_column_int64(stmt_, col); }

 private:
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(file_ + ": " + what + ": " + sqlite3_errmsg(db_));
  }
  sqlite3* db_;
  std::string file_;
  sqlite3_stmt* stmt_ = nullptr;
};

void CollectLeaves(const nlohmann::json& j, const std::string& prefix,
                   std::vector<std::pair<std::string, double>>* out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (prefix.empty() && (it.key() == "seed" || it.key() == "estimator")) continue;
      CollectLeaves(it.value(), prefix.empty() ? it.key() : prefix + "." + it.key(), out);
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      CollectLeaves(j[i], prefix + "[" + std::to_string(i) + "]", out);
    }
  } else if (j.is_number()) {
    out->emplace_back(prefix, j.get<double>());
  } else if (j.is_null()) {
    out->emplace_back(prefix, std::nan(""));  // written as null by nlohmann for NaN
  }
}

}  // namespace

ResultsStore::ResultsStore(const std::filesystem::path& file, Access access)
    : file_(file), db_(std::make_unique<Db>()) {
  db_->file = file.string();
  if (access == Access::kRead) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) {
      throw InputError(db_->file + ": no such results store");
    }
  }
  const int flags = access == Access::kRead ? SQLITE_OPEN_READONLY
                                            : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
  if (sqlite3_open_v2(file.c_str(), &db_->handle, flags, nullptr) != SQLITE_OK) {
    db_->Fail("cannot open");
  }
  sqlite3_busy_timeout(db_->handle, 60000);
  // The schema version (SQLite's user_version) is checked before anything is written: a store of
  // a newer statebench, or another SQLite file, is refused as it is.
  const int version = static_cast<int>(db_->Integer("PRAGMA user_version"));
  const bool has_tables = db_->Integer("SELECT count(*) FROM sqlite_master WHERE type = 'table'") > 0;
  const bool has_runs =
      db_->Integer("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'runs'") > 0;
  if (version > kSchemaVersion) {
    throw InputError(db_->file + ": results store of schema version " + std::to_string(version) +
                     "; this statebench reads version " + std::to_string(kSchemaVersion) +
                     " (written by a newer statebench?)");
  }
  if (has_tables && !has_runs) {
    throw InputError(db_->file + ": an SQLite file but not a results store (no table 'runs')");
  }
  if (access == Access::kRead) {
    if (!has_runs) throw InputError(db_->file + ": not a results store (no table 'runs')");
    return;
  }
  // Version 0 with the tables: written before the version was recorded, the same schema as 1.
  db_->Exec("PRAGMA journal_mode=WAL; PRAGMA foreign_keys=ON; PRAGMA synchronous=NORMAL;");
  db_->Exec(kSchema);
  if (version != kSchemaVersion) {
    db_->Exec("PRAGMA user_version = " + std::to_string(kSchemaVersion));
  }
}

ResultsStore::~ResultsStore() {
  if (db_ && db_->handle) sqlite3_close(db_->handle);
}

void ResultsStore::AddSweep(const SweepRecord& s) {
  Statement st(this, db_->handle, db_->file,
               "INSERT INTO sweeps(name, file, definition, code_version, host, shard, "
               "started_at) VALUES (?, ?, ?, ?, ?, ?, ?)");
  st.Bind(1, s.name).Bind(2, s.file).Bind(3, s.definition).Bind(4, s.code_version);
  st.Bind(5, s.host).Bind(6, s.shard).Bind(7, s.started_at).Run();
}

std::vector<SweepRecord> ResultsStore::Sweeps() const {
  Statement st(this, db_->handle, db_->file,
               "SELECT name, file, definition, code_version, host, shard, started_at FROM sweeps "
               "ORDER BY id");
  std::vector<SweepRecord> sweeps;
  while (st.Step()) {
    sweeps.push_back({st.Text(0), st.Text(1), st.Text(2), st.Text(3), st.Text(4), st.Text(5),
                      st.Text(6)});
  }
  return sweeps;
}

void ResultsStore::WriteRun(const RunRecord& r) {
  db_->Exec("BEGIN IMMEDIATE");
  try {
    {
      Statement del(this, db_->handle, db_->file, "DELETE FROM runs WHERE id = ?");
      del.Bind(1, r.id).Run();
    }
    nlohmann::json parameters = nlohmann::json::object();
    for (const auto& [axis, value] : r.parameters) parameters[axis] = value;
    Statement run(this, db_->handle, db_->file,
                  "INSERT INTO runs(id, sweep, scenario, seed, parameters, code_version, status, "
                  "exit_code, error, wall_s, cpu_s, host, finished_at, run_dir, cache) VALUES "
                  "(?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
    run.Bind(1, r.id).Bind(2, r.sweep).Bind(3, r.scenario);
    run.Bind(4, static_cast<std::int64_t>(r.seed)).Bind(5, parameters.dump());
    run.Bind(6, r.code_version).Bind(7, r.status).Bind(8, std::int64_t{r.exit_code});
    run.Bind(9, r.error).Bind(10, r.wall_s).Bind(11, r.cpu_s).Bind(12, r.host);
    run.Bind(13, r.finished_at).Bind(14, r.run_dir).Bind(15, r.cache.dump()).Run();
    Statement param(this, db_->handle, db_->file,
                    "INSERT INTO run_parameters(run_id, axis, value) VALUES (?, ?, ?)");
    for (const auto& [axis, value] : r.parameters) param.Bind(1, r.id).Bind(2, axis).Bind(3, value).Run();
    Statement metric(this, db_->handle, db_->file,
                     "INSERT OR REPLACE INTO metrics(run_id, estimator, name, value) "
                     "VALUES (?, ?, ?, ?)");
    for (const MetricValue& m : r.metrics) {
      metric.Bind(1, r.id).Bind(2, m.estimator).Bind(3, m.name).Bind(4, m.value).Run();
    }
    Statement artifact(this, db_->handle, db_->file,
                       "INSERT OR REPLACE INTO artifacts(run_id, estimator, kind, path) "
                       "VALUES (?, ?, ?, ?)");
    for (const Artifact& a : r.artifacts) {
      artifact.Bind(1, r.id).Bind(2, a.estimator).Bind(3, a.kind).Bind(4, a.path).Run();
    }
    db_->Exec("COMMIT");
  } catch (...) {
    sqlite3_exec(db_->handle, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::set<std::string> ResultsStore::CompletedRunIds() const {
  Statement st(this, db_->handle, db_->file, "SELECT id FROM runs WHERE status = 'ok'");
  std::set<std::string> ids;
  while (st.Step()) ids.insert(st.Text(0));
  return ids;
}

std::vector<RunRecord> ResultsStore::Runs() const {
  std::vector<RunRecord> runs;
  std::map<std::string, std::size_t> index;
  {
    Statement st(this, db_->handle, db_->file,
                 "SELECT id, sweep, scenario, seed, parameters, code_version, status, exit_code, "
                 "error, wall_s, cpu_s, host, finished_at, run_dir, cache FROM runs ORDER BY id");
    while (st.Step()) {
      RunRecord r;
      r.id = st.Text(0);
      r.sweep = st.Text(1);
      r.scenario = st.Text(2);
      r.seed = static_cast<std::uint64_t>(st.Int(3));
      r.code_version = st.Text(5);
      r.status = st.Text(6);
      r.exit_code = static_cast<int>(st.Int(7));
      r.error = st.Text(8);
      r.wall_s = st.Real(9);
      r.cpu_s = st.Real(10);
      r.host = st.Text(11);
      r.finished_at = st.Text(12);
      r.run_dir = st.Text(13);
      r.cache = nlohmann::json::parse(st.Text(14).empty() ? "{}" : st.Text(14));
      index[r.id] = runs.size();
      runs.push_back(std::move(r));
    }
  }
  {
    Statement st(this, db_->handle, db_->file,
                 "SELECT run_id, axis, value FROM run_parameters ORDER BY run_id, rowid");
    while (st.Step()) runs[index.at(st.Text(0))].parameters.emplace_back(st.Text(1), st.Text(2));
  }
  {
    Statement st(this, db_->handle, db_->file,
                 "SELECT run_id, estimator, name, value FROM metrics ORDER BY run_id, rowid");
    while (st.Step()) {
      runs[index.at(st.Text(0))].metrics.push_back({st.Text(1), st.Text(2), st.Real(3)});
    }
  }
  {
    Statement st(this, db_->handle, db_->file,
                 "SELECT run_id, estimator, kind, path FROM artifacts ORDER BY run_id, rowid");
    while (st.Step()) {
      runs[index.at(st.Text(0))].artifacts.push_back({st.Text(1), st.Text(2), st.Text(3)});
    }
  }
  return runs;
}

std::optional<RunRecord> ResultsStore::Run(const std::string& id) const {
  for (RunRecord& r : Runs()) {
    if (r.id == id) return std::move(r);
  }
  return std::nullopt;
}

std::vector<std::pair<std::string, double>> FlattenMetrics(const nlohmann::json& metrics) {
  std::vector<std::pair<std::string, double>> out;
  CollectLeaves(metrics, "", &out);
  return out;
}

bool IsTimingMetric(const std::string& name) { return name.find("_ms") != std::string::npos; }

bool SameMetricValue(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)) + 1e-12;
}

namespace {

// The first metric two records of one run disagree on, or "".
std::string MetricDifference(const RunRecord& a, const RunRecord& b) {
  std::map<std::pair<std::string, std::string>, double> ma, mb;
  for (const MetricValue& m : a.metrics) {
    if (!IsTimingMetric(m.name)) ma[{m.estimator, m.name}] = m.value;
  }
  for (const MetricValue& m : b.metrics) {
    if (!IsTimingMetric(m.name)) mb[{m.estimator, m.name}] = m.value;
  }
  for (const auto& [key, value] : ma) {
    const auto it = mb.find(key);
    if (it == mb.end()) return key.first + " " + key.second + " is missing in one";
    if (!SameMetricValue(value, it->second)) {
      return key.first + " " + key.second + " " + std::to_string(value) + " vs " +
             std::to_string(it->second);
    }
  }
  return ma.size() == mb.size() ? "" : "different metrics";
}

}  // namespace

std::size_t MergeStores(const std::vector<std::filesystem::path>& inputs,
                        const std::filesystem::path& output) {
  ResultsStore out(output);
  std::map<std::string, std::pair<RunRecord, std::string>> merged;  // id -> run, its store
  for (const RunRecord& r : out.Runs()) merged[r.id] = {r, output.string()};
  std::size_t written = 0;
  for (const std::filesystem::path& input : inputs) {
    const ResultsStore in(input, ResultsStore::Access::kRead);
    for (const SweepRecord& s : in.Sweeps()) out.AddSweep(s);
    for (const RunRecord& r : in.Runs()) {
      const auto it = merged.find(r.id);
      if (it != merged.end()) {
        const RunRecord& have = it->second.first;
        if (r.status != "ok") continue;  // a failure gives way to anything already there
        if (have.status == "ok") {
          const std::string difference = MetricDifference(have, r);
          if (!difference.empty()) {
            throw InputError("run " + r.id + " is in " + it->second.second + " and in " +
                             input.string() + " with different results (" + difference + ")");
          }
          continue;
        }
      }
      out.WriteRun(r);
      merged[r.id] = {r, input.string()};
      ++written;
    }
  }
  return written;
}

}  // namespace statebench::reports
