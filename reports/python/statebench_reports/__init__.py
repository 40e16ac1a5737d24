"""StateBench's HTML reports: one self-contained page per report, drawn with Plotly.

`statebench report` and `statebench compare --out` gather the data and the statistics (C++) into
a job file and run one entry point per report (docs/reports.md):

    python3 -m statebench_reports.run_report JOB.json      # one run folder
    python3 -m statebench_reports.sweep_report JOB.json    # a sweep's results store
    python3 -m statebench_reports.compare_report JOB.json  # a regression comparison

Each writes job["out"], with the plotly.js bundle job["plotly_js"] inlined: the page opens
offline, from a file, with nothing else. Exit code 0 when written, 2 when the input is bad (one
line on stderr naming the file, line and field), 1 for any other failure.
"""
