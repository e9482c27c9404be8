"""consumer.py PROGRAM STOCK PART OUT SUMMARY: the C++ consumer's job
(tests/consumer/main.cpp) from Python, through an installed deflex package:
compensates PROGRAM on STOCK with the part model PART, writes the program to
OUT and the run's summary.json to SUMMARY (cmake/consumer_test.cmake compares
both with the command line's)."""
import json
import sys

import deflex

program, stock, part, out, summary = sys.argv[1:6]
result = deflex.Job(program=program, stock=stock, part=part).compensate(output=out, rows=False)
with open(summary, "w") as f:
    # summary.json's layout (report::document): two-space indent, a final line end.
    f.write(json.dumps(result.summary, indent=2) + "\n")
print(f"{result.summary['compensated_points']} points compensated")
