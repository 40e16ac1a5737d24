#include "apps/process_pool.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace statebench::app {

double MonotonicSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double CpuSeconds(const rusage& usage) {
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

void ProcessPool::StartFunction(std::size_t token, const std::function<int()>& body,
                                const std::filesystem::path& stdout_file,
                                const std::filesystem::path& stderr_file) {
  const double begin_s = MonotonicSeconds();
  // What the parent has buffered must not be written a second time by the child.
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(126);
    const int out = open(stdout_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(stderr_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || err < 0) _exit(126);
    dup2(out, STDOUT_FILENO);
    dup2(err, STDERR_FILENO);
    close(out);
    close(err);
    int code = 1;
    try {
      code = body();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
    } catch (...) {
      std::fprintf(stderr, "error: unknown failure\n");
    }
    std::fflush(stdout);
    std::fflush(stderr);
    _exit(code);  // no destructors or atexit handlers of the parent's objects
  }
  const double now_s = MonotonicSeconds();
  children_[pid] = {token, now_s};
  start_s_ += now_s - begin_s;
}

ChildExit ProcessPool::WaitAny() {
  if (children_.empty()) throw std::logic_error("ProcessPool::WaitAny: no child runs");
  while (true) {
    int status = 0;
    rusage usage{};
    const pid_t pid = wait4(-1, &status, 0, &usage);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("wait failed: ") + std::strerror(errno));
    }
    const auto it = children_.find(pid);
    if (it == children_.end()) continue;
    ChildExit exit;
    exit.token = it->second.token;
    exit.wall_s = MonotonicSeconds() - it->second.start_s;
    exit.cpu_s = CpuSeconds(usage);
    if (WIFEXITED(status)) {
      exit.exit_code = WEXITSTATUS(status);
    } else if (WIFSIGNALED(status)) {
      exit.signal = WTERMSIG(status);
      exit.exit_code = 128 + exit.signal;
    }
    children_.erase(it);
    return exit;
  }
}

}  // namespace statebench::app
