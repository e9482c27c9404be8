#!/usr/bin/env python3
"""The predicted surface error along the tool path of the six-surface sample
(Smaoui et al. 2011), as written and compensated, through `import deflex`.

    python3 examples/plot_error.py error.png [--pass Y_MM]

Run from the source tree (the sample and ./config.yaml are found there) with
the package importable (PYTHONPATH=build/python, or installed). One
compensation gives both curves: each row of the compensated program carries
the error of the program as written at the same place (points.csv's
surface_error_as_written_mm), so the sample is simulated once, inside it.
The plot shows one pass across the six surfaces (the pass nearest Y_MM, default
the pass of the worst point as written: the extremes matter, not the median)
against X, and below it the error's distribution over the whole program.
"""

import argparse
import sys

import matplotlib

matplotlib.use("Agg")  # a file, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import deflex  # noqa: E402

SAMPLE = dict(program="samples/programs/six_surfaces.nc", stock="samples/stock/six_surfaces_stock.stl",
              part="samples/parts/six_surfaces.stl")


def one_pass(points, y_mm):
    """The rows of the pass nearest y_mm (the zig-zag runs along X at constant Y)."""
    y = points["y_mm"]
    nearest = y[np.argmin(np.abs(y - y_mm))]
    return np.abs(y - nearest) < 1e-6


def plot(result, png, y_mm):
    p = result.points
    tol = result.tolerance_mm
    if y_mm is None:  # the pass of the largest |error| as written
        y_mm = p["y_mm"][np.nanargmax(np.abs(p["surface_error_as_written_mm"]))]
    sel = one_pass(p, y_mm)
    order = np.argsort(p["x_mm"][sel])
    x = p["x_mm"][sel][order]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(10, 7), constrained_layout=True)
    top.plot(x, 1000 * p["surface_error_as_written_mm"][sel][order], label="as written")
    top.plot(x, 1000 * p["surface_error_mm"][sel][order], label="compensated")
    for t in (tol, -tol):
        top.axhline(1000 * t, color="grey", linestyle="--", linewidth=0.8)
    top.set(xlabel="X, mm", ylabel="surface error, um (> 0: material left)",
            title=f"{SAMPLE['program']}: pass at Y {p['y_mm'][sel][0]:.1f} mm")
    top.legend()
    bins = np.linspace(-3 * tol, 3 * tol, 61)
    bottom.hist(1000 * p["surface_error_as_written_mm"], bins=1000 * bins, alpha=0.6, label="as written")
    bottom.hist(1000 * p["surface_error_mm"], bins=1000 * bins, alpha=0.6, label="compensated")
    bottom.set(xlabel="surface error, um", ylabel="CL points", title="the whole program")
    bottom.legend()
    fig.savefig(png, dpi=100)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("png", help="the plot to write (PNG)")
    ap.add_argument("--pass", dest="y_mm", type=float, default=None,
                    help="the pass nearest this Y, mm (default: the pass of the worst point as written)")
    a = ap.parse_args(argv)
    result = deflex.Job(**SAMPLE).compensate()  # the compensated program stays in memory: not needed here
    e0, e1 = result.error_as_written, result.error
    print(f"max |error| {e0.max_abs_mm:.4f} mm as written, {e1.max_abs_mm:.4f} mm compensated "
          f"({100 * e0.share_outside:.1f}% / {100 * e1.share_outside:.1f}% of {e1.points} points outside "
          f"+-{result.tolerance_mm} mm)")
    plot(result, a.png, a.y_mm)
    print(f"wrote {a.png}")


if __name__ == "__main__":
    main(sys.argv[1:])
