#!/usr/bin/env python3
"""Measurements of a machine you describe, for a dry run of the fit loop:
what a CMM or the machine's probe would report if the machine were exactly
the profile a simulation ran on (plus Gaussian noise).

    deflex simulate testcut.nc --machine hidden.yaml ... --report sim/
    python3 examples/synthetic_measurement.py sim/ --diameter 12 --csv measured.csv
    python3 examples/synthetic_measurement.py sim/ --diameter 12 \\
        --probe-program probe.nc --log probe_results.txt [--dprnt]

It reads the report's points.csv (each CL point's tip and wall normal) and
flank_profile.csv (the error e(z) of every flank cut over its wall), so only
walls cut with the flank of a flat or bull-nose end are measured. A wall
point at height z above the tip lies D/2 from the axis against the normal's
horizontal part; the machined surface stands e(z) out from it along the
normal (e > 0: material left, deflex's sign).

--csv: one measured surface point per flank sample (every --every'th).
--log: per (DEFLEX PROBE ...) target of the probe program, the stylus ball's
centre where it would trip - the intended point moved out by the ball radius
plus the error there - as LinuxCNC's (PROBEOPEN) file writes it (nine
numbers per line), or with --dprnt as the program's DPRNT lines.
A target with no flank sample within --reach mm is an error: the probe
program is not for this cut.

Only numpy; the nearest sample is found by brute force in chunks (a test
cut has tens of thousands of samples, not millions).
"""

import argparse
import csv
import re
import sys

import numpy as np

PROBE = re.compile(r"\(DEFLEX PROBE (\d+) (\w+) AT (\S+) (\S+) (\S+) N (\S+) (\S+) (\S+) BALL (\S+)\)")


def flank_samples(report, diameter_mm):
    """Wall points, outward normals and errors of every flank slice."""
    normals = {}
    with open(f"{report}/points.csv", newline="") as f:
        for r in csv.DictReader(f):
            normals[(r["x_mm"], r["y_mm"], r["z_mm"])] = (float(r["nx"]), float(r["ny"]), float(r["nz"]))
    at, nrm, err = [], [], []
    with open(f"{report}/flank_profile.csv", newline="") as f:
        for r in csv.DictReader(f):
            n = normals.get((r["x_mm"], r["y_mm"], r["z_tip_mm"]))
            if n is None:
                continue
            h = np.array([n[0], n[1], 0.0])
            if np.linalg.norm(h) < 1e-9:
                continue
            h /= np.linalg.norm(h)
            tip = np.array([float(r["x_mm"]), float(r["y_mm"]), float(r["z_tip_mm"])])
            at.append(tip + np.array([0, 0, float(r["z_mm"])]) - diameter_mm / 2 * h)
            nrm.append(n)
            err.append(float(r["error_mm"]))
    if not at:
        sys.exit(f"{report}: no flank samples (run deflex simulate with --report on a program that cuts walls)")
    return np.array(at), np.array(nrm), np.array(err)


def nearest(samples, points, reach_mm):
    """Index of the nearest sample of each point, -1 beyond reach; of samples
    at the same distance the later one (the pass that cut last), as deflex
    matches them (fit::Nearest)."""
    out = np.empty(len(points), dtype=int)
    for i in range(0, len(points), 256):
        d = np.linalg.norm(points[i:i + 256, None, :] - samples[None, :, :], axis=2)
        k = d.shape[1] - 1 - d[:, ::-1].argmin(axis=1)
        out[i:i + 256] = np.where(d[np.arange(len(k)), k] <= reach_mm, k, -1)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("report", help="the --report folder of deflex simulate on the machine to measure")
    ap.add_argument("--diameter", type=float, required=True, help="the cutter's diameter, mm")
    ap.add_argument("--noise-um", type=float, default=1.0, help="Gaussian noise of each measurement, um (default 1)")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--csv", help="write surface points x_mm,y_mm,z_mm here")
    ap.add_argument("--every", type=int, default=1, help="--csv: every n-th flank sample")
    ap.add_argument("--probe-program", help="the probe program (deflex probe) whose log to write")
    ap.add_argument("--log", help="write the probe log here")
    ap.add_argument("--dprnt", action="store_true", help="--log as a Fanuc's DPRNT output, else LinuxCNC's")
    ap.add_argument("--reach", type=float, default=0.5, help="a target farther than this from every sample is an error, mm")
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    at, nrm, err = flank_samples(a.report, a.diameter)
    noise = lambda n: rng.normal(0.0, a.noise_um / 1000.0, n)  # noqa: E731
    if a.csv:
        idx = np.arange(0, len(at), a.every)
        pts = at[idx] + (err[idx] + noise(len(idx)))[:, None] * nrm[idx]
        with open(a.csv, "w") as f:
            f.write(f"# synthetic: {a.report}, noise {a.noise_um} um\nx_mm,y_mm,z_mm\n")
            for p in pts:
                f.write(f"{p[0]:.6f},{p[1]:.6f},{p[2]:.6f}\n")
    if a.log:
        if not a.probe_program:
            sys.exit("--log needs --probe-program")
        targets = [m.groups() for m in PROBE.finditer(open(a.probe_program).read())]
        if not targets:
            sys.exit(f"{a.probe_program}: no (DEFLEX PROBE ...) comments")
        pt = np.array([[float(t[2]), float(t[3]), float(t[4])] for t in targets])
        n = np.array([[float(t[5]), float(t[6]), float(t[7])] for t in targets])
        r = np.array([float(t[8]) for t in targets])
        k = nearest(at, pt, a.reach)
        if (k < 0).any():
            sys.exit(f"{a.probe_program}: target {targets[int(np.argmax(k < 0))][0]} lies farther than {a.reach} mm "
                     "from every wall of the simulation")
        centre = pt + (r + err[k] + noise(len(k)))[:, None] * n
        with open(a.log, "w") as f:
            if a.dprnt:
                f.write("%\n")
            for t, c in zip(targets, centre):
                if a.dprnt:
                    f.write(f"PT{t[0]} X{c[0]:10.4f} Y{c[1]:10.4f} Z{c[2]:10.4f}\n")
                else:
                    f.write(" ".join(f"{v:.6f}" for v in (*c, 0, 0, 0, 0, 0, 0)) + "\n")
            if a.dprnt:
                f.write("%\n")


if __name__ == "__main__":
    main()
