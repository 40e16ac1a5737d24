#include "simulator/sumo_tools.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/random.hpp"

extern char** environ;

namespace statebench::sim {
namespace {

namespace fs = std::filesystem;

fs::path FindExecutable(const std::vector<fs::path>& dirs, const std::string& name) {
  for (const fs::path& dir : dirs) {
    const fs::path candidate = dir / name;
    if (::access(candidate.c_str(), X_OK) == 0 && !fs::is_directory(candidate)) return candidate;
  }
  return {};
}

std::vector<fs::path> SplitSearchPath(const std::string& search_path) {
  std::vector<fs::path> dirs;
  std::stringstream ss(search_path);
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    if (!dir.empty()) dirs.emplace_back(dir);
  }
  return dirs;
}

SumoTools FindInDirs(const std::vector<fs::path>& dirs) {
  SumoTools tools;
  tools.netgenerate = FindExecutable(dirs, "netgenerate");
  tools.netconvert = FindExecutable(dirs, "netconvert");
  tools.duarouter = FindExecutable(dirs, "duarouter");
  return tools;
}

// The parent's environment with SUMO_HOME defaulted.
std::vector<std::string> ChildEnvironment() {
  std::vector<std::string> env;
  bool has_home = false;
  for (char** e = environ; e != nullptr && *e != nullptr; ++e) {
    env.emplace_back(*e);
    has_home = has_home || std::strncmp(*e, "SUMO_HOME=", 10) == 0;
  }
  if (!has_home) env.push_back("SUMO_HOME=" + SumoHome());
  return env;
}

std::string Tail(const fs::path& file, std::size_t max_chars) {
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  if (text.size() > max_chars) text = "..." + text.substr(text.size() - max_chars);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text;
}

}  // namespace

std::int64_t SumoSeed(std::uint64_t seed, std::string_view stream_name) {
  return static_cast<std::int64_t>(StreamSeed(seed, stream_name) % 2147483647u);
}

std::string SumoHome() {
  const char* home = std::getenv("SUMO_HOME");
  return home != nullptr && *home != '\0' ? home : "/usr/share/sumo";
}

SumoTools SumoTools::Find() {
  const char* path = std::getenv("PATH");
  std::vector<fs::path> dirs = SplitSearchPath(path != nullptr ? path : "");
  dirs.push_back(fs::path(SumoHome()) / "bin");
  return FindInDirs(dirs);
}

SumoTools SumoTools::FindIn(const std::string& search_path) {
  return FindInDirs(SplitSearchPath(search_path));
}

ToolRun RunTool(const fs::path& tool, const std::vector<std::string>& args,
                const fs::path& log_file) {
  std::vector<std::string> argv_store = {tool.string()};
  argv_store.insert(argv_store.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_store) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_store = ChildEnvironment();
  std::vector<char*> envp;
  for (std::string& e : env_store) envp.push_back(e.data());
  envp.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_file.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);

  ToolRun run;
  pid_t pid = 0;
  const int spawn_error =
      posix_spawn(&pid, tool.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (spawn_error != 0) {
    run.log_tail = "could not start " + tool.string() + ": " + std::strerror(spawn_error);
    return run;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) break;
  }
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.log_tail = Tail(log_file, 2000);
  return run;
}

}  // namespace statebench::sim
