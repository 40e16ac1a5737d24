// statebench: the command line of the StateBench estimator and test bench.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "apps/commands.hpp"

namespace {

constexpr const char* kUsage =
    "usage: statebench <command> [args]\n"
    "commands:\n"
    "  simulate SCENARIO.yaml --out DIR   exact ground truth of a scenario (SUMO + vehicle model)\n"
    "  record SCENARIO.yaml --out LOG     simulate every sensor of the scenario's setup into a log\n"
    "  estimate LOG --out DIR             run the factor-graph estimator on a recorded log\n"
    "  run SCENARIO.yaml --out DIR        simulation, sensors and estimators in one process, scored\n"
    "  odometry LOG --out DIR             lidar-only odometry of a recorded log (TUM, KITTI error)\n"
    "  suite [DIR] --out OUT              every scenario of DIR (scenarios/paper) with run, in\n"
    "                                     parallel; Table I of the paper beside ours\n"
    "  sweep SWEEP.yaml --out DIR         Monte Carlo sweep: many runs into a results store\n"
    "  results summary|merge DB ...       statistics of a results store; merge shard stores\n"
    "  compare BASE CANDIDATE             regression verdicts between two stores or run folders\n"
    "  report RUN_DIR|DB --out FILE.html  HTML report with plots of a run or a sweep's store\n"
    "  import rosbag BAG [--topics MAP.yaml --out LOG]\n"
    "                                     a ROS1 bag into a recorded log (without --topics: its\n"
    "                                     topics and a suggested MAP.yaml)\n"
    "  export rosbag LOG --out BAG        a recorded log into a ROS1 bag\n"
    "Run 'statebench <command> --help' for a command's options.\n";

}  // namespace

int main(int argc, char** argv) {
  // Vehicle and sensor-setup files named in a scenario are also looked up in the source tree's
  // scenarios/ folder, so scenarios kept elsewhere can name the stock vehicles.
  setenv("STATEBENCH_SOURCE_DIR", STATEBENCH_DEFAULT_SOURCE_DIR, /*overwrite=*/0);
  setenv("SUMO_HOME", "/usr/share/sumo", /*overwrite=*/0);
  if (argc < 2) {
    std::fprintf(stderr, "%s", kUsage);
    return 2;
  }
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  if (command == "simulate") return statebench::app::RunSimulate(args);
  if (command == "record") return statebench::app::RunRecord(args);
  if (command == "estimate") return statebench::app::RunEstimate(args);
  if (command == "run") return statebench::app::RunRun(args);
  if (command == "odometry") return statebench::app::RunOdometry(args);
  if (command == "suite") return statebench::app::RunSuite(args);
  if (command == "sweep") return statebench::app::RunSweep(args);
  if (command == "results") return statebench::app::RunResults(args);
  if (command == "compare") return statebench::app::RunCompare(args);
  if (command == "report") return statebench::app::RunReportCommand(args);
  if (command == "import") return statebench::app::RunImport(args);
  if (command == "export") return statebench::app::RunExport(args);
  if (command == "--help" || command == "help" || command == "-h") {
    std::printf("%s", kUsage);
    return 0;
  }
  std::fprintf(stderr, "statebench: unknown command '%s'\n%s", command.c_str(), kUsage);
  return 2;
}
