// The HTML reports' drawing half: a small Python package (reports/python/statebench_reports,
// docs/reports.md) that turns a job file into one self-contained HTML page with Plotly figures.
// statebench's commands gather the data (run folders, results stores, comparisons) and the
// statistics in C++, write them into the job and run the package's entry point for the report.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace statebench::app {

// Where the pieces are: the Python interpreter ($STATEBENCH_PYTHON, else Debian's
// /usr/bin/python3, else python3 on the PATH), the package folder
// ($STATEBENCH_SOURCE_DIR/reports/python) and the plotly.js bundle every page inlines
// ($STATEBENCH_PLOTLY_JS, else the one scripts/setup.sh installs with npm under
// $STATEBENCH_SOURCE_DIR/third_party/npm).
struct HtmlReportTools {
  std::string python;
  std::filesystem::path package_dir;
  std::filesystem::path plotly_js;
};
// Throws std::runtime_error naming what is missing and how to get it.
HtmlReportTools FindHtmlReportTools();

// Writes `job` (plus "out" and "plotly_js") into a temporary file and runs
// `python -m statebench_reports.<module> JOB`, which writes the page to `out`. Throws InputError
// with the package's message when it refused its input (exit code 2), std::runtime_error with
// the end of its stderr for any other failure.
void RenderHtmlReport(const std::string& module, nlohmann::json job,
                      const std::filesystem::path& out);

}  // namespace statebench::app
