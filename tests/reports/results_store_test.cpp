#include "reports/results_store.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"

namespace statebench::reports {
namespace {

namespace fs = std::filesystem;

class ResultsStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("results_store_test_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static RunRecord MakeRun(const std::string& id, double x) {
    RunRecord r;
    r.id = id;
    r.sweep = "s";
    r.scenario = "setup2";
    r.seed = 7;
    r.parameters = {{"cep_m", "2"}, {"window_s", "1.5"}};
    r.code_version = "abc";
    r.status = "ok";
    r.wall_s = 1.5;
    r.cpu_s = 2.5;
    r.cache = {{"sumo", {{"hits", 1}, {"misses", 0}}}};
    r.metrics = {{"factor_graph", "rmse.x_m", x}, {"ekf", "rmse.x_m", 2 * x},
                 {"ekf", "nees.pose_6dof_mean", std::nan("")}};
    r.artifacts = {{"ekf", "metrics", "/tmp/x/ekf/metrics.json"}};
    return r;
  }

  fs::path dir_;
};

TEST_F(ResultsStoreTest, RunsComeBackWithEveryRow) {
  {
    ResultsStore store(dir_ / "a.db");
    store.AddSweep({"s", "s.yaml", "name: s", "abc", "host", "", "2026-01-01T00:00:00Z"});
    store.WriteRun(MakeRun("r1", 0.5));
    RunRecord failed = MakeRun("r2", 0.0);
    failed.status = "failed";
    failed.exit_code = 2;
    failed.error = "exit code 2: boom";
    failed.metrics.clear();
    store.WriteRun(failed);
  }
  const ResultsStore store(dir_ / "a.db");
  EXPECT_EQ(store.Sweeps().size(), 1u);
  EXPECT_EQ(store.CompletedRunIds(), std::set<std::string>{"r1"});
  const std::vector<RunRecord> runs = store.Runs();
  ASSERT_EQ(runs.size(), 2u);
  const RunRecord& r = runs[0];
  EXPECT_EQ(r.id, "r1");
  EXPECT_EQ(r.parameters, MakeRun("r1", 0.5).parameters);
  ASSERT_EQ(r.metrics.size(), 3u);
  EXPECT_EQ(r.metrics[0], (MetricValue{"factor_graph", "rmse.x_m", 0.5}));
  EXPECT_TRUE(std::isnan(r.metrics[2].value));
  EXPECT_EQ(r.artifacts, MakeRun("r1", 0.5).artifacts);
  EXPECT_EQ(r.cache["sumo"]["hits"], 1);
  EXPECT_EQ(runs[1].status, "failed");
  EXPECT_EQ(runs[1].error, "exit code 2: boom");
}

TEST_F(ResultsStoreTest, WritingARunAgainReplacesIt) {
  ResultsStore store(dir_ / "a.db");
  store.WriteRun(MakeRun("r1", 0.5));
  store.WriteRun(MakeRun("r1", 0.25));
  const std::vector<RunRecord> runs = store.Runs();
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].metrics[0].value, 0.25);
  EXPECT_EQ(runs[0].metrics.size(), 3u);
}

TEST_F(ResultsStoreTest, MergeKeepsEveryRunOnceAndRefusesConflicts) {
  {
    ResultsStore a(dir_ / "a.db");
    a.WriteRun(MakeRun("r1", 0.5));
    RunRecord failed = MakeRun("r2", 0.0);
    failed.status = "failed";
    a.WriteRun(failed);
    ResultsStore b(dir_ / "b.db");
    b.WriteRun(MakeRun("r1", 0.5));
    b.WriteRun(MakeRun("r2", 0.75));  // the failed run succeeded elsewhere
    ResultsStore c(dir_ / "c.db");
    c.WriteRun(MakeRun("r1", 0.6));  // same run, another result
  }
  EXPECT_EQ(MergeStores({dir_ / "a.db", dir_ / "b.db"}, dir_ / "all.db"), 3u);
  const ResultsStore all(dir_ / "all.db");
  EXPECT_EQ(all.CompletedRunIds(), (std::set<std::string>{"r1", "r2"}));
  try {
    MergeStores({dir_ / "a.db", dir_ / "c.db"}, dir_ / "conflict.db");
    FAIL() << "a run with two results was merged";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("run r1"), std::string::npos) << e.what();
  }
}

// Runs one statement on an SQLite file directly, as another program would.
void ExecSql(const fs::path& file, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sql;
  sqlite3_close(db);
}

int UserVersion(const fs::path& file) {
  sqlite3* db = nullptr;
  sqlite3_open(file.c_str(), &db);
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &stmt, nullptr);
  sqlite3_step(stmt);
  const int version = sqlite3_column_int(stmt, 0);
  sqlite3_finalize(stmt);
  sqlite3_close(db);
  return version;
}

TEST_F(ResultsStoreTest, SchemaVersionIsRecordedAndANewerOrForeignFileRefused) {
  { ResultsStore store(dir_ / "a.db"); }
  EXPECT_EQ(UserVersion(dir_ / "a.db"), ResultsStore::kSchemaVersion);

  // A store written before the version was recorded (0) is the same layout: it opens.
  {
    ResultsStore store(dir_ / "old.db");
    store.WriteRun(MakeRun("r1", 0.5));
  }
  ExecSql(dir_ / "old.db", "PRAGMA user_version = 0");
  EXPECT_EQ(ResultsStore(dir_ / "old.db").Runs().size(), 1u);
  EXPECT_EQ(UserVersion(dir_ / "old.db"), ResultsStore::kSchemaVersion);

  ExecSql(dir_ / "a.db", "PRAGMA user_version = 99");
  try {
    ResultsStore store(dir_ / "a.db");
    FAIL() << "a store of schema version 99 was opened";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a.db: results store of schema version 99; this "
                                         "statebench reads version 1"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(UserVersion(dir_ / "a.db"), 99);  // left as it was

  ExecSql(dir_ / "other.db", "CREATE TABLE t (x INTEGER)");
  EXPECT_THROW(ResultsStore(dir_ / "other.db"), InputError);
  std::ofstream(dir_ / "text.db") << "not a database, just a text file of some length\n";
  EXPECT_THROW(ResultsStore(dir_ / "text.db"), InputError);
}

// A reader (summary, compare, report) opens the store read-only: it never creates a file, never
// writes, and reads a store a writer still holds open.
TEST_F(ResultsStoreTest, ReadAccessNeitherCreatesNorWrites) {
  using Access = ResultsStore::Access;
  EXPECT_THROW(ResultsStore(dir_ / "missing.db", Access::kRead), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "missing.db"));
  ResultsStore writer(dir_ / "a.db");
  writer.WriteRun(MakeRun("r1", 0.5));
  {
    const ResultsStore reader(dir_ / "a.db", Access::kRead);
    ASSERT_EQ(reader.Runs().size(), 1u);
    EXPECT_EQ(reader.Runs()[0].id, "r1");
  }
  writer.WriteRun(MakeRun("r2", 0.7));
  EXPECT_EQ(ResultsStore(dir_ / "a.db", Access::kRead).Runs().size(), 2u);
  ExecSql(dir_ / "other.db", "CREATE TABLE t (x INTEGER)");
  EXPECT_THROW(ResultsStore(dir_ / "other.db", Access::kRead), InputError);
}

TEST(FlattenMetrics, NestedKeysListsAndNoIdentifiers) {
  const nlohmann::json j = {{"seed", 3},
                            {"estimator", "ekf"},
                            {"rmse", {{"x_m", 0.5}}},
                            {"outages", {{{"error_end_m", 1.5}}}},
                            {"name", "text"}};
  const auto flat = FlattenMetrics(j);
  ASSERT_EQ(flat.size(), 2u);
  EXPECT_EQ(flat[0].first, "outages[0].error_end_m");
  EXPECT_EQ(flat[1].first, "rmse.x_m");
  EXPECT_EQ(flat[1].second, 0.5);
}

}  // namespace
}  // namespace statebench::reports
