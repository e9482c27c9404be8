#!/bin/sh
# The Z-map cell-size convergence study (docs/benchmarks.md, "Cell size: the
# study"). For each case, `deflex simulate --report` at each cell of CELLS
# (default "0.025 0.05 0.1 0.2"; the first is the reference), and for the
# six-surface sample and the raster also `deflex compensate --report`; each
# run's points.csv is compared point by point with the reference's
# (bench/cell_compare.py: |de| in um, |dF| in N and %, a_p / a_e, the compensation
# offset), and each compensated program with the reference's by `deflex diff`
# (the largest distance between their end points: the difference of the
# offsets deflex wrote, 0.001 mm resolution as written). Prints the headline
# figures, the wall and CPU time and the peak memory of every run (each under
# nice, --threads 1), then per cell the comparison (columns: the docstring of
# bench/cell_compare.py). About 5 minutes on a 2-core machine.
#
#   sh bench/cell_study.sh            after building build/deflex
#   CELLS="0.025 0.05 0.1 0.2"        cell sizes, mm, reference first
#   CASES="six raster corpus"         which cases
#   CORPUS="cameo bear flower_mold wave"
#   BLOCKS=100000                     the raster's size (bench/gen_program.sh)
#   REST=sweep|zmap                   corpus rest stock: the earlier programs
#                                     swept at each cell (--stock-from, default),
#                                     or swept once at the reference cell into
#                                     a .zmap read back at each cell
#   OUT=bench/out/cell  THREADS=1
set -eu
cd "$(dirname "$0")/.."
cells=${CELLS:-0.025 0.05 0.1 0.2}
cases=${CASES:-six raster corpus}
corpus_progs=${CORPUS:-cameo bear flower_mold wave}
out=${OUT:-bench/out/cell}
threads=${THREADS:-1}
rest_mode=${REST:-sweep}
deflex=build/deflex
py=/usr/bin/python3
cmp=bench/cell_compare.py
[ -x "$deflex" ] || { echo "cell_study.sh: build first (build/deflex)" >&2; exit 2; }
ref=${cells%% *}
mkdir -p "$out"
echo "cell study: $(nproc) cores, $(uname -m), $(sed -n 's/^model name[^:]*: //p' /proc/cpuinfo | head -n 1); load $(cut -d' ' -f1-3 /proc/loadavg)"
echo "deflex $($deflex --version 2>&1 | head -n 1); cells $cells (reference $ref); --threads $threads"

# run DIR CMD ARGS...: one deflex run under nice, its stdout and stderr in DIR,
# wall time, peak memory and CPU time (GNU time) in DIR/time.
run() {
  d=$1; shift
  mkdir -p "$d"
  if ! /usr/bin/time -f "%e %M %U %S" -o "$d/time" nice "$deflex" "$@" --threads "$threads" >"$d/stdout" 2>"$d/stderr"; then
    echo "FAILED: deflex $* (see $d/stderr)" >&2
    tail -n 3 "$d/stderr" >&2
    return 1
  fi
}

# The headline of a run: max, rms, share outside the tolerance.
headline_sim() {  # DIR
  sed -n 's/.*CL points: surface error max \([0-9.]*\) mm, rms \([0-9.]*\) mm, \([0-9.]*%\) outside +-\([0-9.]*\) mm.*/max \1 rms \2 mm, \3 outside +-\4/p' "$1/stdout" "$1/stderr" | head -n 1
}
headline_comp() {  # DIR
  w=$(sed -n 's/.*predicted error, as written: max \([0-9.]*\) mm, rms \([0-9.]*\) mm, \([0-9.]*%\) of.*/\1 \2 \3/p' "$1/stderr")
  c=$(sed -n 's/.*predicted error, compensated: max \([0-9.]*\) mm, rms \([0-9.]*\) mm, \([0-9.]*%\) of.*/\1 \2 \3/p' "$1/stderr")
  n=$(sed -n 's/.*: \([0-9]*\) points compensated.*/\1/p' "$1/stderr")
  echo "written max/rms/out $w; compensated $c; $n pts comp"
}
# Wall time, CPU time (user + system: what the run costs when the machine is
# shared) and peak memory.
wall() { awk '{ printf "%6.1f s wall %6.1f s cpu %5.0f MB", $1, $3 + $4, $2 / 1024 }' "$1/time"; }

# study NAME KIND(simulate|compensate) PROGRAM ARGS...: the runs at every
# cell, then the table against the reference.
study() {
  name=$1; kind=$2; prog=$3; shift 3
  base=$out/$name/$kind
  echo
  echo "== $name: deflex $kind $prog $*"
  for c in $cells; do
    d=$base/$c
    rm -rf "$d/report"
    if [ "$kind" = compensate ]; then
      run "$d" compensate "$prog" "$@" --cell-mm "$c" --report "$d/report" -o "$d/comp.nc" || continue
      echo "  cell $c: $(wall "$d") | $(headline_comp "$d")"
    else
      run "$d" simulate "$prog" "$@" --cell-mm "$c" --report "$d/report" || continue
      echo "  cell $c: $(wall "$d") | $(headline_sim "$d")"
    fi
  done
  pair=xyz; [ "$kind" = compensate ] && pair=order
  $py $cmp header | sed 's/^/  /'
  for c in $cells; do
    [ "$c" = "$ref" ] && continue
    if [ ! -f "$base/$c/report/points.csv" ] || [ ! -f "$base/$ref/report/points.csv" ]; then continue; fi
    $py $cmp points "$base/$ref/report/points.csv" "$base/$c/report/points.csv" --pair $pair --label "$c" --detail | sed 's/^/  /'
  done
  if [ "$kind" = compensate ]; then
    for c in $cells; do
      [ "$c" = "$ref" ] && continue
      if [ ! -f "$base/$c/comp.nc" ] || [ ! -f "$base/$ref/comp.nc" ]; then continue; fi
      # deflex diff exits 1 where blocks were inserted differently: not a failure here.
      "$deflex" diff "$base/$ref/comp.nc" "$base/$c/comp.nc" >"$base/$c/diff.txt" 2>&1 || true
      echo "  program $c against $ref: $(tail -n 1 "$base/$c/diff.txt")"
    done
  fi
}

for case in $cases; do
  case $case in
  six)
    # The bundled sample as scripts/main.sh compensates it (with its part model).
    for kind in simulate compensate; do
      study six_surfaces $kind samples/programs/six_surfaces.nc --stock samples/stock/six_surfaces_stock.stl \
        --part samples/parts/six_surfaces.stl
    done
    ;;
  raster)
    n=${BLOCKS:-100000}
    f=bench/data/finish_$n.nc; st=bench/data/stock_${n}_0.5.stl
    [ -f "$f" ] || sh bench/gen_program.sh "$n" "$f" >/dev/null
    [ -f "$st" ] || sh bench/gen_stock.sh "$n" "$st" 0.5 >/dev/null
    # As bench/compensate.sh runs it.
    for kind in simulate compensate; do
      study "raster_$n" "$kind" "$f" --stock "$st" --tool T5 --tolerance 0.002
    done
    ;;
  corpus)
    # As scripts/corpus.sh runs them: the roughing (flat D10, 0.5 mm) and the
    # semi-finishing pass (the finishing ball, 0.2 mm, 1 mm apart) generated
    # once by `deflex rough` (its own target cell, 0.1 mm), then the finishing
    # program on the blank with both swept in.
    for name in $corpus_progs; do
      case $name in
      cameo) prog=cameo.nc; blank=box:-75,-93.7,-10,75,93.3,0; finish=T7; extra="--spindle 10000"; dia="" ;;
      bear) prog=bear.nc; blank=box:0,0,-20,80,80,0; finish=T3; extra=""; dia="" ;;
      flower_mold) prog=flower_mold.nc; blank=box:0,0,-12,57.15,57.15,0; finish=T3; extra=""; dia="" ;;
      wave) prog=wave.gcode; blank=box:0,0,-5,92,92,0; finish=T3; extra="--dialect linuxcnc"; dia=$extra ;;
      *) echo "cell_study.sh: no corpus program $name" >&2; exit 2 ;;
      esac
      d=$out/corpus_$name
      mkdir -p "$d"
      # shellcheck disable=SC2086  # $extra is a list of options
      [ -f "$d/rough.nc" ] || $deflex rough "tests/data/corpus/$prog" --stock "$blank" --tool "$finish" --rough-tool T1 \
        --allowance 0.5 -o "$d/rough.nc" $extra 2>"$d/rough.log"
      # shellcheck disable=SC2086
      [ -f "$d/semi.nc" ] || $deflex rough "tests/data/corpus/$prog" --stock "$blank" --tool "$finish" --rough-tool "$finish" \
        --allowance 0.2 --stepdown 0 --stepover 1 -o "$d/semi.nc" $extra 2>"$d/semi.log"
      if [ "$rest_mode" = zmap ]; then
        z=$d/rest_$ref.zmap
        if [ ! -f "$z" ]; then
          # shellcheck disable=SC2086
          /usr/bin/time -f "%e %M" -o "$d/rest.time" nice $deflex stock --stock "$blank" --stock-from "$d/rough.nc" \
            --stock-from "$d/semi.nc" --cell-mm "$ref" -o "$z" $dia 2>"$d/rest.log"
          echo "  rest stock of $name at $ref mm: $(awk '{ printf "%.1f s", $1 }' "$d/rest.time")"
        fi
        stock_args="--stock $z"; label=corpus_${name}_zmap
      else
        label=corpus_$name
        stock_args="--stock $blank --stock-from $d/rough.nc --stock-from $d/semi.nc"
      fi
      # shellcheck disable=SC2086
      study "$label" simulate "tests/data/corpus/$prog" $stock_args --tool "$finish" \
        --material Al7075-T6 $extra
    done
    ;;
  *) echo "cell_study.sh: unknown case $case" >&2; exit 2 ;;
  esac
done
