#!/bin/sh
# The CAM corpus (tests/data/corpus, programs written by others) run as a shop
# would run them: for each finishing program, `deflex rough` generates the
# roughing (flat D10, 0.5 mm allowance) and a semi-finishing pass (the
# finishing ball, 0.2 mm, lines 1 mm apart), both are swept into the blank
# with --stock-from, and the finishing program is compensated on that stock -
# and, for comparison, on the bare blank (where the finishing tool's holder or
# shank would run into it, the row says so: compensate refuses such a program). Prints one table row per program and
# stock; everything lands in OUT (default bench/out/corpus).
#   sh scripts/corpus.sh [OUT]          after sh scripts/test.sh (uses build/deflex)
set -eu
cd "$(dirname "$0")/.."
out=${1:-bench/out/corpus}
corpus=tests/data/corpus
deflex=build/deflex
[ -x "$deflex" ] || { echo "corpus.sh: build first (sh scripts/test.sh)" >&2; exit 2; }
[ -d "$corpus" ] || { echo "corpus.sh: $corpus not found (a clone holds it)" >&2; exit 2; }
mkdir -p "$out"

# The blanks (work frame, mm) cover each program's path; the corpus names no
# tool library, so the finishing tool is chosen from samples/tools.yaml (T7
# ball D10, T3 ball D6), and a spindle speed where the program gives none.
# program            blank                              finish  extra options
jobs='cameo.nc        box:-75,-93.7,-10,75,93.3,0        T7      --spindle 10000
bear.nc              box:0,0,-20,80,80,0                T3      -
flower_mold.nc       box:0,0,-12,57.15,57.15,0          T3      -
wave.gcode           box:0,0,-5,92,92,0                 T3      --dialect linuxcnc'

# One row from a run's points.csv and stderr: a_p max, |F| max, the largest
# surface error as written and after compensation, and the number of points
# the roughing warning names.
row() {  # name stock dir
  awk -F, -v name="$1" -v stock="$2" 'NR > 1 {
      if ($6 > ap) ap = $6
      f = sqrt($11 * $11 + $12 * $12 + $13 * $13); if (f > fm) fm = f
      e = $17 < 0 ? -$17 : $17; if (e > em) em = e
      w = $18 < 0 ? -$18 : $18; if (w > wm) wm = w
      n++ }
    END { printf "%-15s %-12s %8d %9.2f %9.0f %9.4f %9.4f", name, stock, n, ap, fm, wm, em }' "$3/report/points.csv"
  rough=$(sed -n 's/.*; \([0-9]*\) points on [0-9]* lines.*\[roughing\].*/\1/p' "$3/stderr")
  echo " $(printf '%9s' "${rough:-0}")"
}

printf '%-15s %-12s %8s %9s %9s %9s %9s %9s\n' program stock points "a_p max" "|F| max" "error" "after" roughing
printf '%-15s %-12s %8s %9s %9s %9s %9s %9s\n' "" "" "" mm N "mm" "mm" "points"
echo "$jobs" | while read -r prog blank finish extra; do
  [ "$extra" = "-" ] && extra=""
  name=${prog%.*}
  d=$out/$name
  mkdir -p "$d"
  # shellcheck disable=SC2086  # $extra is a list of options
  $deflex rough "$corpus/$prog" --stock "$blank" --tool "$finish" --rough-tool T1 --allowance 0.5 \
    -o "$d/rough.nc" $extra 2>"$d/rough.log"
  # shellcheck disable=SC2086
  $deflex rough "$corpus/$prog" --stock "$blank" --tool "$finish" --rough-tool "$finish" --allowance 0.2 \
    --stepdown 0 --stepover 1 -o "$d/semi.nc" $extra 2>"$d/semi.log"
  for stock in blank rough+semi; do
    r=$d/$stock
    mkdir -p "$r"
    from=""
    [ "$stock" = blank ] || from="--stock-from $d/rough.nc --stock-from $d/semi.nc"
    # A program whose holder or shank runs into the stock is refused (exit
    # 1, nothing written): its row names the errors instead of the figures.
    # shellcheck disable=SC2086
    if $deflex compensate "$corpus/$prog" --stock "$blank" $from --tool "$finish" --material Al7075-T6 \
      --report "$r/report" -o "$r/comp.nc" $extra 2>"$r/stderr"; then
      row "$name" "$stock" "$r"
    else
      printf '%-15s %-12s refused: %s\n' "$name" "$stock" \
        "$(sed -n 's/.*error: \(the [a-z]* of T[0-9]*\).* runs \([0-9.]*\) mm .*/\1 \2 mm in the material/p' "$r/stderr" | head -n 1)"
    fi
  done
done
