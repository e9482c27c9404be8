#!/usr/bin/python3
"""Compares the points.csv of a run at one Z-map cell size with the reference
run's (the finest cell), point by point (bench/cell_study.sh).

    cell_compare.py header
    cell_compare.py points REF_CSV RUN_CSV [--pair xyz|order] [--label L] [--detail]

prints one table row: the points paired, those in material in one run only
(and the largest |e| among them), |de| (surface_error_mm) in um: median, p95,
max, the program line of the max and e there (reference > run); the criterion
"within 0.2 um or 2 % of the reference" as r = |de| / max(0.2 um, 0.02 |e_ref|)
(median, p95, max: r <= 1 meets it) and the number of points with r > 1;
|dF| (the vector difference of Fx, Fy, Fz) in N and relative to |F| where
|F| > 10 N; the largest |da_p|, |da_e| and |d offset_mm| in um. --detail adds
where the largest relative force and a_p differences lie and, for
compensate, the points compensated at both cell sizes and at one only (the
tolerance decides: a point inside it stays as programmed).

Pairing: `xyz` (simulate) pairs the rows of the same program line and the same
commanded tip (the CL samples along a move do not depend on the cell; a row is
written only for a point in material, so a point in air at one cell size has
no partner); `order` (compensate, whose tip is the compensated one) pairs the
k-th row of a line with the k-th row of the same line, where both runs have
the same number of rows on that line. Unpaired rows are counted, never paired
by their position in the file.

Standard library only.
"""
import csv
import math
import sys

ABS_UM = 0.2     # the criterion: |de| <= 0.2 um ...
REL = 0.02       # ... or |de| <= 2 % of |e| of the reference
F_MIN_N = 10.0   # relative force differences where |F_ref| > 10 N


def read(path):
    with open(path, newline="") as f:
        r = csv.reader(f)
        head = next(r)
        col = {name: i for i, name in enumerate(head)}
        need = ["line", "x_mm", "y_mm", "z_mm", "surface_error_mm", "offset_mm", "Fx_N", "Fy_N", "Fz_N"]
        missing = [n for n in need if n not in col]
        if missing:
            sys.exit(f"{path}: no column {', '.join(missing)} in {head}")
        rows = list(r)
    return col, rows


def num(s):
    return float(s) if s != "" else math.nan


def keyed(col, rows, pair):
    out = {}
    if pair == "xyz":
        ix = [col["line"], col["x_mm"], col["y_mm"], col["z_mm"]]
        seen = {}
        for row in rows:
            k = tuple(row[i] for i in ix)
            n = seen.get(k, 0)
            seen[k] = n + 1
            out[k + (n,)] = row
    else:
        by_line = {}
        for row in rows:
            by_line.setdefault(row[col["line"]], []).append(row)
        for line, rs in by_line.items():
            out[line] = rs
    return out


def pct(sorted_vals, q):
    """Nearest-rank percentile of an ascending list (q in [0, 100])."""
    if not sorted_vals:
        return math.nan
    k = max(0, min(len(sorted_vals) - 1, math.ceil(q / 100.0 * len(sorted_vals)) - 1))
    return sorted_vals[k]


def stats(vals):
    v = sorted(x for x in vals if not math.isnan(x))
    return pct(v, 50), pct(v, 95), (v[-1] if v else math.nan)


def compare(ref_csv, run_csv, pair):
    cref, rref = read(ref_csv)
    crun, rrun = read(run_csv)
    kref = keyed(cref, rref, pair)
    krun = keyed(crun, rrun, pair)
    pairs = []
    if pair == "xyz":
        for k, a in kref.items():
            b = krun.get(k)
            if b is not None:
                pairs.append((a, b))
        only_ref = len(kref) - len(pairs)
        only_run = len(krun) - len(pairs)
    else:
        only_ref = only_run = 0
        for line, ra in kref.items():
            rb = krun.get(line, [])
            if len(ra) == len(rb):
                pairs.extend(zip(ra, rb))
            else:
                only_ref += len(ra)
                only_run += len(rb)
        only_run += sum(len(rb) for line, rb in krun.items() if line not in kref)
    # The largest |e| among the points in material at one cell size only: what
    # the unpaired points would hide.
    def e_of(c, row):
        return abs(num(row[c["surface_error_mm"]])) * 1000.0
    paired_ids_ref = {id(a) for a, _ in pairs}
    paired_ids_run = {id(b) for _, b in pairs}
    unp = [e_of(cref, r) for r in rref if id(r) not in paired_ids_ref] + \
          [e_of(crun, r) for r in rrun if id(r) not in paired_ids_run]
    unp = [x for x in unp if not math.isnan(x)]

    de, crit, dF, dFrel, dap, dae, doff = [], [], [], [], [], [], []
    flips, both = [], []  # compensate: points compensated at one cell size only / at both
    worst = (-1.0, "", 0.0, 0.0)
    # The points where each difference is largest, for the detail lines.
    at = {"dF%": (-1.0, None, None), "dap": (-1.0, None, None)}
    for a, b in pairs:
        ea, eb = num(a[cref["surface_error_mm"]]), num(b[crun["surface_error_mm"]])
        if math.isnan(ea) or math.isnan(eb):
            continue
        d = abs(eb - ea) * 1000.0  # um
        de.append(d)
        crit.append(d / max(ABS_UM, REL * abs(ea) * 1000.0))
        if d > worst[0]:
            worst = (d, a[cref["line"]], ea * 1000.0, eb * 1000.0)
        fa = [num(a[cref[c]]) for c in ("Fx_N", "Fy_N", "Fz_N")]
        fb = [num(b[crun[c]]) for c in ("Fx_N", "Fy_N", "Fz_N")]
        df = math.sqrt(sum((x - y) ** 2 for x, y in zip(fa, fb)))
        dF.append(df)
        fn = math.sqrt(sum(x * x for x in fa))
        if fn > F_MIN_N:
            dFrel.append(100.0 * df / fn)
            if dFrel[-1] > at["dF%"][0]:
                at["dF%"] = (dFrel[-1], a, b)
        oa, ob = num(a[cref["offset_mm"]]), num(b[crun["offset_mm"]])
        doff.append(abs(oa - ob) * 1000.0)
        if (oa == 0.0) != (ob == 0.0):
            # Compensated at one cell size only: the point's |e| straddles the
            # tolerance (points inside it stay as programmed).
            flips.append((abs(ea if oa == 0.0 else eb) * 1000.0, d, doff[-1]))
        elif oa != 0.0:
            both.append((d, doff[-1]))
        if "ap_mm" in cref and "ap_mm" in crun:
            dap.append(abs(num(a[cref["ap_mm"]]) - num(b[crun["ap_mm"]])) * 1000.0)
            if dap[-1] > at["dap"][0]:
                at["dap"] = (dap[-1], a, b)
        if "ae_mm" in cref and "ae_mm" in crun:
            dae.append(abs(num(a[cref["ae_mm"]]) - num(b[crun["ae_mm"]])) * 1000.0)
    return {
        "paired": len(de), "only_ref": only_ref, "only_run": only_run,
        "unpaired_e_max": max(unp) if unp else 0.0,
        "de": stats(de), "worst": worst,
        "fail": sum(1 for x in crit if x > 1.0), "crit": stats(crit), "at": at, "cols": (cref, crun),
        "dF": stats(dF), "dFrel": stats(dFrel), "dap": stats(dap), "dae": stats(dae),
        "doff": stats(doff), "flips": flips, "both": both,
    }


COLS = [  # name, unit, width
    ("cell", "mm", 6), ("paired", "", 7), ("ref/run", "only", 9), ("e_unp", "um", 6),
    ("de p50", "um", 7), ("de p95", "um", 7), ("de max", "um", 7), ("line", "of max", 7),
    ("e ref>run", "um", 13), ("r p50", "crit", 6), ("r p95", "", 6), ("r max", "", 6), ("fail", "pts", 5),
    ("dF p50", "N", 6), ("dF p95", "N", 6), ("dF max", "N", 7),
    ("%F p50", "|F|>10N", 7), ("%F p95", "", 6), ("%F max", "", 6),
    ("dap max", "um", 7), ("dae max", "um", 7), ("doff max", "um", 8),
]


def line_of(cells):
    return " ".join(str(c).rjust(w) if i else str(c).ljust(w) for i, (c, (_, _, w)) in enumerate(zip(cells, COLS)))


def row(label, r):
    d, w = r["de"], r["worst"]
    f2 = lambda x: "%.2f" % x
    f3 = lambda x: "%.3f" % x
    f1 = lambda x: "%.1f" % x
    return line_of([
        label, r["paired"], "%d/%d" % (r["only_ref"], r["only_run"]), f2(r["unpaired_e_max"]),
        f3(d[0]), f3(d[1]), f3(d[2]), w[1], "%.2f>%.2f" % (w[2], w[3]),
        f2(r["crit"][0]), f2(r["crit"][1]), f2(r["crit"][2]), r["fail"],
        f2(r["dF"][0]), f2(r["dF"][1]), f2(r["dF"][2]),
        f2(r["dFrel"][0]), f2(r["dFrel"][1]), f1(r["dFrel"][2]),
        f1(r["dap"][2]), f1(r["dae"][2]), f2(r["doff"][2])])


def details(r):
    """Where the largest force and a_p differences lie: line, tip, |F|, a_p, a_e, e."""
    cref, crun = r["cols"]
    out = []
    for what, (v, a, b) in r["at"].items():
        if a is None:
            continue
        def desc(c, row):
            f = math.sqrt(sum(num(row[c[k]]) ** 2 for k in ("Fx_N", "Fy_N", "Fz_N")))
            return "|F| %.1f N a_p %s a_e %s e %.2f um" % (f, row[c["ap_mm"]], row[c["ae_mm"]],
                                                         num(row[c["surface_error_mm"]]) * 1000.0)
        unit = "%" if what == "dF%" else "um"
        out.append("    max %s %.1f %s at line %s (%s, %s, %s): ref %s; run %s" % (
            what, v, unit, a[cref["line"]], a[cref["x_mm"]], a[cref["y_mm"]], a[cref["z_mm"]],
            desc(cref, a), desc(crun, b)))
    if r["flips"] or r["both"]:
        f, b = r["flips"], r["both"]
        line = "    compensated at both: %d points, |d offset| p50/p95/max %.3f/%.3f/%.3f um, |de| max %.3f um" % (
            len(b), *stats([x[1] for x in b]), max([x[0] for x in b], default=0.0))
        if f:
            line += "; at one only: %d points (left alone there at |e| <= %.3f um), |d offset| max %.3f um, |de| max %.3f um" % (
                len(f), max(x[0] for x in f), max(x[2] for x in f), max(x[1] for x in f))
        out.append(line)
    return "\n".join(out)


def main(argv):
    args = argv[1:]
    if args and args[0] == "header":
        print(line_of([c[0] for c in COLS]))
        print(line_of([c[1] for c in COLS]))
        return 0
    if len(args) < 3 or args[0] != "points":
        sys.exit(__doc__)
    pair, label, detail = "xyz", args[2], False
    rest = args[3:]
    while rest:
        if rest[0] == "--pair":
            pair = rest[1]
            rest = rest[2:]
        elif rest[0] == "--detail":
            detail = True
            rest = rest[1:]
        elif rest[0] == "--label":
            label = rest[1]
            rest = rest[2:]
        else:
            sys.exit(f"unknown option {rest[0]}")
    r = compare(args[1], args[2], pair)
    print(row(label, r))
    if detail:
        print(details(r))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
