#!/usr/bin/env python3
"""Writes slot_tests_al7075.csv: synthetic slot tests for `deflex calibrate`.

The mean forces come from the closed form of a full slot with a flat end mill
(Altintas 2012 ch. 2; deflex sign convention: forces on the tool, feed +X,
spindle M3, Fz = -Fa) with the TRUE coefficients below, plus 0.5 % Gaussian
noise (fixed seed, so the file is reproducible). tests/force/test_calibration.cpp
checks that `deflex calibrate` recovers TRUE from this file.
"""
import math
import random

TRUE = dict(Ktc=850.0, Krc=290.0, Kac=120.0, Kte=24.0, Kre=31.0, Kae=1.8)
FLUTES, DIAMETER, HELIX = 4, 12.0, 30.0
FEEDS = [0.025, 0.05, 0.075, 0.1, 0.125, 0.15]
DEPTHS = [3.0, 5.0]
NOISE = 0.005


def slot_mean(fz, ap):
    na = FLUTES * ap
    k = TRUE
    return (na * (-k["Krc"] * fz / 4 - k["Kre"] / math.pi),
            na * (k["Ktc"] * fz / 4 + k["Kte"] / math.pi),
            na * (-k["Kac"] * fz / math.pi - k["Kae"] / 2))


def main():
    rng = random.Random(4)
    lines = [
        "# deflex slot-test calibration data (synthetic, see make_slot_tests.py)",
        "# Full-immersion slots, mean forces on the tool in machine axes (N):",
        "# feed +X, spindle M3 (clockwise from above), Z up.",
        "# generated with K_tc 850, K_rc 290, K_ac 120 N/mm^2; K_te 24, K_re 31, K_ae 1.8 N/mm; 0.5% noise",
        "# material: Al7075-T6 (synthetic)",
        "# tool: flat end mill D 12 mm, 4 flutes, helix 30 deg",
        f"# diameter_mm: {DIAMETER:g}",
        f"# flutes: {FLUTES}",
        f"# helix_deg: {HELIX:g}",
        "# forces_on: tool",
        "ap_mm,fz_mm,Fx_N,Fy_N,Fz_N",
    ]
    for ap in DEPTHS:
        for fz in FEEDS:
            f = [v * (1 + rng.gauss(0, NOISE)) for v in slot_mean(fz, ap)]
            lines.append(f"{ap:g},{fz:g},{f[0]:.2f},{f[1]:.2f},{f[2]:.2f}")
    with open("slot_tests_al7075.csv", "w", encoding="ascii") as out:
        out.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
