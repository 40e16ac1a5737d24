// statebench report on bad input: a clear message naming the file and exit code 2, nothing
// written (a missing run folder, a store of an unknown schema version or without runs, an axis
// the store lacks, a run folder with a bad run.json or a bad cell in a CSV file).
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "reports/results_store.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code = -1;
  std::string output;
};

class ReportCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("report_command_test_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Outcome Statebench(const std::string& args) {
    const fs::path log = dir_ / "output.log";
    const int status = std::system(
        (std::string(STATEBENCH_BIN) + " " + args + " > " + log.string() + " 2>&1").c_str());
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
  }

  // Expects exit code 2, `message` in the output and no report written.
  void ExpectRefused(const std::string& args, const std::string& message) {
    SCOPED_TRACE(args);
    fs::remove(dir_ / "out.html");
    const Outcome o = Statebench("report " + args + " --out " + (dir_ / "out.html").string());
    EXPECT_EQ(o.exit_code, 2) << o.output;
    EXPECT_NE(o.output.find(message), std::string::npos) << o.output;
    EXPECT_FALSE(fs::exists(dir_ / "out.html"));
  }

  static void SetUserVersion(const fs::path& file, int version) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
    const std::string sql = "PRAGMA user_version = " + std::to_string(version);
    ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }

  fs::path dir_;
};

TEST_F(ReportCommandTest, BadInputIsRefusedWithAClearMessage) {
  ExpectRefused((dir_ / "missing").string(), "missing: no such run folder or results store");
  fs::create_directories(dir_ / "empty");
  ExpectRefused((dir_ / "empty").string(),
                "empty: neither a run folder (run.json) nor a results store (results.db)");

  // Stores: one without runs, one of a newer schema version, one whose runs lack the axis.
  { reports::ResultsStore store(dir_ / "none.db"); }
  ExpectRefused((dir_ / "none.db").string(), "none.db: the store holds no run");
  {
    reports::ResultsStore store(dir_ / "store.db");
    reports::RunRecord run;
    run.id = "r1";
    run.scenario = "s";
    run.status = "failed";
    run.parameters = {{"cep_m", "1"}};
    store.WriteRun(run);
  }
  fs::copy_file(dir_ / "store.db", dir_ / "newer.db");
  SetUserVersion(dir_ / "newer.db", 7);
  ExpectRefused((dir_ / "newer.db").string(),
                "newer.db: results store of schema version 7; this statebench reads version 1");
  ExpectRefused((dir_ / "store.db").string() + " --by window_s",
                "no axis 'window_s' in the store (axes: cep_m, scenario, seed)");

  // A run folder: a short run, then copies with a broken run.json and a bad estimate cell.
  const Outcome run = Statebench("run scenarios/extra/setup1_quadricycle_nolidar.yaml --duration 4 "
                                 "--estimators ekf --quiet --out " + (dir_ / "run").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ExpectRefused((dir_ / "run").string() + " --by cep_m",
                "--by is for a sweep's results store, not a run folder");
  fs::copy(dir_ / "run", dir_ / "bad_json", fs::copy_options::recursive);
  std::ofstream(dir_ / "bad_json" / "run.json") << "{\"scenario\": \"x\",\n";
  ExpectRefused((dir_ / "bad_json").string(), "bad_json/run.json: not JSON");
  fs::copy(dir_ / "run", dir_ / "bad_cell", fs::copy_options::recursive);
  {
    std::ifstream in(dir_ / "bad_cell" / "ekf" / "estimate.csv");
    std::string header, first, rest;
    std::getline(in, header);
    std::getline(in, first);
    std::stringstream tail;
    tail << in.rdbuf();
    first = first.substr(0, first.find(',') + 1) + "abc" + first.substr(first.find(',', first.find(',') + 1));
    std::ofstream(dir_ / "bad_cell" / "ekf" / "estimate.csv") << header << "\n" << first << "\n" << tail.str();
  }
  ExpectRefused((dir_ / "bad_cell").string(), "ekf/estimate.csv:2: column 'p_x': unexpected value 'abc'");
}

}  // namespace
}  // namespace statebench::app
