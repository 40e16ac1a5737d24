#include "apps/html_report.hpp"

#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPlotlyPackage = "plotly.js-basic-dist-min";

std::string Environment(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

std::string ReadAll(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The last `lines` lines of a text, without the trailing newline.
std::string Tail(const std::string& text, int lines) {
  std::string t = text;
  while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
  std::size_t start = t.size();
  for (int i = 0; i < lines && start > 0; ++i) {
    start = t.rfind('\n', start - 1);
    if (start == std::string::npos) return t;
  }
  return t.substr(start + 1);
}

}  // namespace

HtmlReportTools FindHtmlReportTools() {
  const fs::path source = Environment("STATEBENCH_SOURCE_DIR").empty()
                              ? fs::path(".")
                              : fs::path(Environment("STATEBENCH_SOURCE_DIR"));
  HtmlReportTools tools;
  tools.python = Environment("STATEBENCH_PYTHON");
  if (tools.python.empty()) {
    tools.python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  }
  tools.package_dir = source / "reports" / "python";
  if (!fs::is_directory(tools.package_dir / "statebench_reports")) {
    throw std::runtime_error("the report package is missing: no " +
                             (tools.package_dir / "statebench_reports").string() +
                             " (STATEBENCH_SOURCE_DIR names the source tree)");
  }
  const std::string plotly = Environment("STATEBENCH_PLOTLY_JS");
  tools.plotly_js = plotly.empty() ? source / "third_party" / "npm" / "node_modules" /
                                         kPlotlyPackage / "plotly-basic.min.js"
                                   : fs::path(plotly);
  if (!fs::is_regular_file(tools.plotly_js)) {
    throw std::runtime_error("plotly.js not found at " + tools.plotly_js.string() +
                             ": run scripts/setup.sh (it installs " + kPlotlyPackage +
                             " with npm), or set STATEBENCH_PLOTLY_JS to a plotly.js bundle");
  }
  return tools;
}

void RenderHtmlReport(const std::string& module, nlohmann::json job, const fs::path& out) {
  const HtmlReportTools tools = FindHtmlReportTools();
  job["out"] = fs::absolute(out).string();
  job["plotly_js"] = fs::absolute(tools.plotly_js).string();
  const fs::path temp = fs::temp_directory_path() /
                        ("statebench_report_" + std::to_string(getpid()) + "_" + module);
  const fs::path job_file = temp.string() + ".json";
  const fs::path stderr_file = temp.string() + ".stderr";
  {
    std::ofstream f(job_file);
    f << job.dump();
    if (!f) throw std::runtime_error(job_file.string() + ": cannot write the report's job file");
  }
  const std::string module_name = "statebench_reports." + module;
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    std::FILE* err = std::fopen(stderr_file.c_str(), "w");
    if (err) dup2(fileno(err), STDERR_FILENO);
    std::string pythonpath = tools.package_dir.string();
    if (!Environment("PYTHONPATH").empty()) pythonpath += ":" + Environment("PYTHONPATH");
    setenv("PYTHONPATH", pythonpath.c_str(), 1);
    setenv("PYTHONDONTWRITEBYTECODE", "1", 1);
    const char* argv[] = {tools.python.c_str(), "-m", module_name.c_str(), job_file.c_str(),
                          nullptr};
    execvp(argv[0], const_cast<char* const*>(argv));
    std::fprintf(stderr, "cannot start %s: %s\n", argv[0], std::strerror(errno));
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const std::string messages = ReadAll(stderr_file);
  fs::remove(job_file);
  fs::remove(stderr_file);
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  if (code == 0) return;
  if (code == 2) throw InputError(Tail(messages, 1));
  throw std::runtime_error(module_name + " (" + tools.python + ") failed with exit code " +
                           std::to_string(code) + ":\n" + Tail(messages, 15));
}

}  // namespace statebench::app
