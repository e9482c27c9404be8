"""deflex.Job.fit: the fitted profile from Python equals the command line's,
and a fit on the examples' synthetic measurements reaches the noise."""

import subprocess
import sys

import deflex
from conftest import DEFLEX

RUN = dict(program="tests/data/fit/walls_xy.nc", machine="samples/machines/mill3.yaml", material="Al6082-T4",
           stock="box:0,0,-20,100,100,0")


def test_fit_from_python_is_the_command_lines(tmp_path):
    # Measurements of the machine described by mill3_as_built, as a CMM would give them.
    report = tmp_path / "as_built"
    deflex.Job(**dict(RUN, machine="samples/machines/mill3_as_built.yaml", report_dir=str(report))).simulate(rows=False)
    csv = tmp_path / "measured.csv"
    subprocess.run([sys.executable, "examples/synthetic_measurement.py", str(report), "--diameter", "12", "--csv", str(csv),
                    "--every", "9"], check=True)
    r = deflex.Job(**dict(RUN, measured=str(csv))).fit()
    assert r["compared_points"] == r["measured_points"] > 100
    assert r["rms_after_mm"] < 0.5 * r["rms_before_mm"]
    held = [name for name, p in r["parameters"].items() if not p["fitted"]]
    assert "structure Z" in held and all(r["parameters"][n]["why_held"] for n in held)
    x = r["parameters"]["structure X"]
    assert x["fitted"] and x["interval95"][0] <= x["factor"] <= x["interval95"][1]
    # The command line writes the same profile.
    out = tmp_path / "fitted.yaml"
    subprocess.run([DEFLEX, "fit", RUN["program"], "--machine", RUN["machine"], "--material", RUN["material"],
                    "--stock", RUN["stock"], "--measured", str(csv), "-o", str(out)], check=True, capture_output=True)
    assert out.read_text() == r["profile"]
