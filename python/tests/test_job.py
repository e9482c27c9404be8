"""deflex.Job on the six-surface sample against the command line and its own
points.csv; progress; from_file."""

import csv
import math

import numpy as np

import deflex
from conftest import SAMPLE

# points.csv's decimals per column (src/report/recorder.cpp write_csv): the
# rows, unrounded, equal the CSV within half a unit of the last place.
DECIMALS = {"x_mm": 4, "y_mm": 4, "z_mm": 4, "path_mm": 3, "ap_mm": 4, "ae_mm": 4, "d_eff_mm": 4,
            "cwe_area_mm2": 4, "mrr_mm3_per_s": 2, "Fx_N": 2, "Fy_N": 2, "Fz_N": 2, "flank_z_min_mm": 4,
            "flank_z_max_mm": 4, "stepover_mm": 4, "power_kW": 4, "torque_Nm": 3, "ap_limit_mm": 4}


def test_compensate_gives_the_cli_bytes(cli_compensated, py_compensated):
    cli_bytes, _ = cli_compensated
    assert py_compensated.output is None
    assert py_compensated.program_bytes == cli_bytes
    assert py_compensated.program.encode("utf-8", "surrogateescape") == cli_bytes


def test_compensate_summary_is_the_cli_summary_json(cli_compensated, py_compensated):
    _, summary = cli_compensated
    assert py_compensated.summary == summary
    # summary.json rounds to 6 decimals (report/summary.cpp); the figures are unrounded.
    assert math.isclose(py_compensated.error.max_abs_mm, summary["surface_error_mm"]["max"], abs_tol=5e-7)
    assert py_compensated.error_as_written.points == summary["cl_points"]
    # The compensation is worth having on this sample (scripts/main.sh prints it).
    assert py_compensated.error.max_abs_mm < py_compensated.error_as_written.max_abs_mm
    assert isinstance(py_compensated.messages, str)


def test_compensate_rows_carry_both_programs(py_compensated):
    p = py_compensated.points
    n = len(p["line"])
    assert n > 1000 and all(len(v) == n for v in p.values())
    written = p["surface_error_as_written_mm"]
    assert np.nanmax(np.abs(written)) > np.nanmax(np.abs(p["surface_error_mm"]))


def read_points_csv(path):
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        return header, list(reader)


def test_simulate_columns_are_points_csv(py_simulated):
    result, report, _ = py_simulated
    header, rows = read_points_csv(report / "points.csv")
    assert list(result.points) == header
    assert len(rows) == len(result.points["line"]) > 1000
    for k, name in enumerate(header):
        column = result.points[name]
        text = [r[k] for r in rows]
        if name == "normal_source":
            assert column.dtype == object and list(column) == text
            continue
        if name == "line":
            assert column.dtype == np.int64 and list(column) == [int(t) for t in text]
            continue
        assert column.dtype == np.float64
        expected = np.array([float(t) if t else np.nan for t in text])
        assert np.array_equal(np.isnan(column), np.isnan(expected)), name
        tol = 0.5 * 10.0 ** -DECIMALS.get(name, 6) + 1e-12
        both = ~np.isnan(expected)
        assert np.max(np.abs(column[both] - expected[both]), initial=0) <= tol, name


def test_simulate_summary_and_figures(py_simulated):
    result, report, _ = py_simulated
    import json
    assert result.summary == json.loads((report / "summary.json").read_text())
    assert result.error.points == result.summary["cl_points"]
    assert math.isclose(result.error.rms_mm, result.summary["surface_error_mm"]["rms"], abs_tol=1e-6)
    assert 0 < result.error.share_outside < 1
    assert result.figures["peak_force_N"] > 0


def test_progress_is_called(py_simulated):
    _, _, calls = py_simulated
    assert calls, "the progress callable was never called"
    assert all(isinstance(s, str) and s and 0.0 <= f <= 1.0 for s, f in calls)


def test_from_file_with_overrides():
    job = deflex.Job.from_file("samples/jobs/six_surfaces.yaml", tolerance_mm=0.02)
    s = job.settings
    assert s["tolerance_mm"] == 0.02  # the keyword wins over the file's 0.01
    assert s["program"].endswith("samples/jobs/../programs/six_surfaces.nc")
    assert s["machine"] == "mill3" and s["material"] == "C35"


def test_settings_round_trip():
    job = deflex.Job(**SAMPLE, stock_from=["a.nc", ("b.nc", "b_tools.yaml")], kt_N_per_mm2=1800.0,
                     block_delete=True, threads=2)
    s = job.settings
    assert s["stock_from"] == ["a.nc", ("b.nc", "b_tools.yaml")]
    assert s["kt_N_per_mm2"] == 1800.0 and s["kr_N_per_mm2"] is None
    assert s["block_delete"] is True and s["threads"] == 2
    assert set(deflex.Job.settings_names()) == set(s)
