#!/bin/bash
# Regenerates the expected output of the golden CLI cases from a deflex binary.
# Review every change with `git diff tests/golden` before committing: a golden
# file is a claim that this output is right, not a record of what it happens to be.
#   tests/golden/regen.sh [path/to/deflex]   (run from the repository root)
set -eu
deflex=${1:-build/deflex}
for a in tests/golden/*.args; do
  b=${a%.args}
  mapfile -t args < "$a"
  in=/dev/null; [ -f "$b.stdin" ] && in="$b.stdin"
  set +e; "$deflex" "${args[@]}" < "$in" > "$b.stdout" 2> "$b.stderr"; echo $? > "$b.rc"; set -e
  [ -s "$b.stderr" ] || rm -f "$b.stderr"
done
