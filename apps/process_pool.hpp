// Child processes for the sweep: each run is its own `statebench run` process (libsumo holds one
// simulation per process, and a crash stays in its run), at most `jobs` at a time.
//
// A child's stdout and stderr go to files; it is killed when the parent dies (PR_SET_PDEATHSIG),
// so a killed sweep leaves no run still writing into a folder a resumed sweep will reuse.
//
// Children are forked without exec: each runs a function of the program that is already
// loaded (the sweep's `statebench run`), which saves the ~0.4 s CPU of loading statebench's
// 285 shared libraries (SUMO's GDAL and OpenSceneGraph, PCL's VTK) for every run. Call it only
// while the parent has one thread (fork copies the calling thread alone).
#pragma once

#include <sys/resource.h>
#include <sys/types.h>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <string>

namespace statebench::app {

struct ChildExit {
  std::size_t token = 0;  // what StartFunction() was given
  int exit_code = 0;      // exit status, or 128 + signal
  int signal = 0;         // the signal that ended it, 0 when it exited
  double wall_s = 0.0;
  double cpu_s = 0.0;  // user + system of the child and its own children
};

class ProcessPool {
 public:
  // Forks a child that runs body() with stdout and stderr redirected and exits with its return
  // value (1 with a message when it throws). Throws std::runtime_error when fork fails.
  void StartFunction(std::size_t token, const std::function<int()>& body,
                     const std::filesystem::path& stdout_file,
                     const std::filesystem::path& stderr_file);
  // Waits for one child to end.
  ChildExit WaitAny();
  std::size_t running() const { return children_.size(); }
  // Seconds the parent spent starting children (fork included), in all.
  double start_s() const { return start_s_; }

 private:
  struct Child {
    std::size_t token = 0;
    double start_s = 0.0;
  };
  std::map<pid_t, Child> children_;
  double start_s_ = 0.0;
};

// Seconds on a monotonic clock.
double MonotonicSeconds();

// User + system CPU seconds of a resource usage (wait4's of a child, or getrusage's).
double CpuSeconds(const rusage& usage);

}  // namespace statebench::app
