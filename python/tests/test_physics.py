"""compliance, forces, cusp_height_mm against `deflex stiffness`, `deflex
forces` and the closed form of Miko et al. Eq. 7."""

import json
import math

import numpy as np
import pytest

import deflex
from conftest import run_cli


def test_compliance_is_the_cli_stiffness():
    cli = json.loads(run_cli("stiffness", "--tool-file", "samples/tools.yaml", "--tool", "T5", "--machine", "mill3",
                             "--format", "json").stdout)["compliance"]
    c = deflex.compliance("T5", tool_file="samples/tools.yaml", machine="mill3")
    assert c.matrix_mm_per_N.shape == (len(cli), 3, 3)
    assert np.allclose(c.heights_mm, [row["height_mm"] for row in cli], rtol=1e-6)
    # The CLI prints 7 significant digits (src/stiffness/report.cpp).
    assert np.allclose(c.matrix_mm_per_N, [row["matrix_mm_per_N"] for row in cli], rtol=1e-6, atol=1e-15)
    # Maxwell-Betti: a compliance matrix is symmetric.
    assert np.allclose(c.matrix_mm_per_N, c.matrix_mm_per_N.transpose(0, 2, 1), rtol=1e-9, atol=1e-15)


def test_compliance_at_heights_and_tool_only():
    free = deflex.compliance("T5", tool_file="samples/tools.yaml", heights_mm=[0.0, 5.0])
    held = deflex.compliance("T5", tool_file="samples/tools.yaml", machine="mill3", heights_mm=[0.0, 5.0])
    assert list(free.heights_mm) == [0.0, 5.0]
    # Holder, spindle and machine in series add compliance.
    assert held.matrix_mm_per_N[0, 0, 0] > free.matrix_mm_per_N[0, 0, 0] > 0
    with pytest.raises(deflex.UsageError, match="load height"):
        deflex.compliance("T5", tool_file="samples/tools.yaml", heights_mm=[500.0])


def test_forces_are_the_cli_forces():
    args = dict(tool="T1", tool_file="samples/tools.yaml", material="Al6082-T4", ae_mm=2.5, ap_mm=12, fz_mm=0.1)
    cli = json.loads(run_cli("forces", "--tool-file", "samples/tools.yaml", "--tool", "T1", "--material", "Al6082-T4",
                             "--ae", "2.5", "--ap", "12", "--fz", "0.1", "--down", "--format", "json").stdout)
    f = deflex.forces(**args)
    assert f.force_N.shape == (360, 3) and f.angle_deg[1] == 1.0
    assert np.allclose(f.mean_N, cli["mean_N"], atol=5e-4)
    assert np.allclose(f.peak_abs_N, cli["peak_abs_N"], atol=5e-4)
    assert np.allclose(f.mean_N, f.force_N.mean(axis=0))
    with pytest.raises(deflex.UsageError, match="milling"):
        deflex.forces(**args, milling="climb")


def test_stability_is_the_cli_stability():
    cli = json.loads(run_cli("stability", "--tool-file", "samples/tools.yaml", "--tool", "T1", "--material",
                             "Al7075-T6", "--machine", "mill3", "--ae", "3", "--points", "200", "--format",
                             "json").stdout)
    s = deflex.stability(tool="T1", tool_file="samples/tools.yaml", material="Al7075-T6", machine="mill3", ae_mm=3,
                         points=200)
    assert s.rpm.shape == (201,) and s.ap_limit_mm.shape == (201,)
    assert np.allclose(s.ap_limit_mm, [p[1] for p in cli["limit"]], atol=5e-5)
    assert math.isclose(s.ap_min_mm, cli["ap_min_mm"], abs_tol=5e-5)
    assert len(s.modes) == len(cli["modes"]) == 4
    assert np.all(s.ap_limit_mm >= s.ap_min_mm * (1 - 1e-9))
    with pytest.raises(deflex.UsageError, match="milling"):
        deflex.stability(tool="T1", ae_mm=3, milling="climb")


def test_cusp_height_closed_form():
    # Eq. 7 on a level surface: R - sqrt(R^2 - (a_e/2)^2).
    assert math.isclose(deflex.cusp_height_mm(16, 1.0), 8 - math.sqrt(64 - 0.25), rel_tol=1e-12)
    # Along a level line of a 20 deg slope the step-over on the surface is a_e / cos 20 deg (Eq. 4).
    s = 1.0 / math.cos(math.radians(20))
    assert math.isclose(deflex.cusp_height_mm(16, 1.0, inclination_deg=20, direction_deg=90),
                        8 - math.sqrt(64 - (s / 2) ** 2), rel_tol=1e-9)
    h = deflex.cusp_height_mm(16, np.array([0.5, 1.0, 2.0]))
    assert h.shape == (3,) and np.all(np.diff(h) > 0)
