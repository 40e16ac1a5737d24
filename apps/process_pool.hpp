// Child processes for the sweep: each run is its own `statebench run` process (libsumo holds one
// simulation per process, and a crash stays in its run), at most `jobs` at a time.
//
// A child's stdout and stderr go to files; it is killed when the parent dies (PR_SET_PDEATHSIG),
// so a killed sweep leaves no run still writing into a folder a resumed sweep will reuse.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace statebench::app {

struct ChildExit {
  std::size_t token = 0;  // what Start() was given
  int exit_code = 0;      // exit status, or 128 + signal
  int signal = 0;         // the signal that ended it, 0 when it exited
  double wall_s = 0.0;
  double cpu_s = 0.0;  // user + system of the child and its own children
};

class ProcessPool {
 public:
  // Starts argv[0] (a path) with the arguments; throws std::runtime_error when fork fails. A
  // program that cannot be executed ends with exit code 127 and a message in stderr_file.
  void Start(std::size_t token, const std::vector<std::string>& argv,
             const std::filesystem::path& stdout_file, const std::filesystem::path& stderr_file);
  // Waits for one child to end.
  ChildExit WaitAny();
  std::size_t running() const { return children_.size(); }

 private:
  struct Child {
    std::size_t token = 0;
    double start_s = 0.0;
  };
  std::map<pid_t, Child> children_;
};

// Seconds on a monotonic clock.
double MonotonicSeconds();

}  // namespace statebench::app
