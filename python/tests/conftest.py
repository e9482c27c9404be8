"""Shared fixtures: the six-surface sample run as scripts/main.sh runs it,
through the command line and through Python, once per session (each run is a
few seconds of the entry's ~60 s)."""

import json
import os
import pathlib
import subprocess

import pytest

import deflex

ROOT = pathlib.Path(__file__).resolve().parents[2]
# The CLI the Python results are compared with (CTest sets it: python/CMakeLists.txt).
DEFLEX = os.environ.get("DEFLEX_BINARY", str(ROOT / "build" / "deflex"))
# scripts/main.sh's options; machine, tool and material libraries, material and
# tolerance come from ./config.yaml, as there.
SAMPLE = {
    "program": "samples/programs/six_surfaces.nc",
    "stock": "samples/stock/six_surfaces_stock.stl",
    "part": "samples/parts/six_surfaces.stl",
}
SAMPLE_ARGS = [SAMPLE["program"], "--stock", SAMPLE["stock"], "--part", SAMPLE["part"]]


@pytest.fixture(scope="session", autouse=True)
def in_source_tree():
    """Relative sample paths and ./config.yaml, as the CLI is run in main.sh."""
    old = os.getcwd()
    os.chdir(ROOT)
    yield
    os.chdir(old)


def run_cli(*args):
    return subprocess.run([DEFLEX, *args], cwd=ROOT, capture_output=True, check=True)


@pytest.fixture(scope="session")
def cli_compensated(tmp_path_factory, in_source_tree):
    """`deflex compensate` of the sample: (program bytes, summary.json as a dict)."""
    out = tmp_path_factory.mktemp("cli")
    run_cli("compensate", *SAMPLE_ARGS, "-o", str(out / "comp.nc"), "--report", str(out / "report"))
    return (out / "comp.nc").read_bytes(), json.loads((out / "report" / "summary.json").read_text())


@pytest.fixture(scope="session")
def py_compensated(tmp_path_factory, in_source_tree):
    """The same through Python, the program in memory; with a report, as the
    CLI's (summary.json holds the error's percentiles only then)."""
    report = tmp_path_factory.mktemp("py") / "report"
    return deflex.Job(**SAMPLE, report_dir=str(report)).compensate()


@pytest.fixture(scope="session")
def py_simulated(tmp_path_factory, in_source_tree):
    """The sample simulated with a report (its points.csv beside the rows) and
    a progress callable: (result, report folder, progress calls)."""
    report = tmp_path_factory.mktemp("sim") / "report"
    calls = []
    result = deflex.Job(**SAMPLE, report_dir=str(report)).simulate(progress=lambda s, f: calls.append((s, f)))
    return result, report, calls
