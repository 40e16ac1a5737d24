"""What every entry point shares: reading the job file and turning failures into exit codes."""

import json
import sys
import traceback

from .errors import ReportInputError


def run(build, argv):
    """Calls build(job) with the job file named by argv[1]; returns the process exit code.

    0: the page is written; 2: bad input (ReportInputError: its message alone, one line, on
    stderr); 1: anything else (the traceback on stderr).
    """
    if len(argv) != 2:
        print("usage: python3 -m statebench_reports.<report> JOB.json", file=sys.stderr)
        return 2
    try:
        with open(argv[1], encoding="utf-8") as f:
            job = json.load(f)
        build(job)
        return 0
    except ReportInputError as e:
        print(" ".join(str(e).split("\n")), file=sys.stderr)
        return 2
    except Exception:  # noqa: BLE001 - any other failure is reported whole
        traceback.print_exc()
        return 1
