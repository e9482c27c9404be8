"""Failures as Python exceptions: the class of the failure, its location,
nothing written; Ctrl-C and a raising progress callable stop a run."""

import os
import signal
import threading

import pytest

import deflex
from conftest import SAMPLE

GOOD = "%\nO1\nG21 G90 G17 G54\nT5 M6\nS4000 M3\nG0 X-10 Y5 Z5\nG1 Z-0.5 F800\nG1 X30\nG0 Z5\nM30\n%\n"
STOCK = "box:0,0,-20,40,10,0"


def test_a_bad_program_raises_the_input_error_at_its_line(tmp_path):
    bad = tmp_path / "bad.nc"
    bad.write_text(GOOD.replace("G1 X30\n", "G1 X30 Y\n"))  # line 8: an axis word without a number
    with pytest.raises(deflex.InputError) as e:
        deflex.Job(program=str(bad), stock=STOCK).simulate()
    assert e.value.file == str(bad) and e.value.line == 8 and e.value.column is not None
    assert e.value.exit_code == 1
    assert str(e.value).startswith(f"{bad}:8:")
    assert "error" in e.value.messages
    # The location comes with the failure, not from the printed text.
    assert e.value.errors and all(err[:2] == (str(bad), 8) for err in e.value.errors)
    assert "G1 X30 Y" in e.value.errors[0][3]  # the source line under the message


def test_a_bad_setting_raises_the_usage_error_before_anything_runs(tmp_path):
    out = tmp_path / "out.nc"
    with pytest.raises(deflex.UsageError) as e:
        # The program does not exist: the setting is refused before it is read.
        deflex.Job(program=str(tmp_path / "missing.nc"), stock=STOCK, tolerance_mm=-1).compensate(out)
    assert str(e.value) == "tolerance_mm must be > 0 mm" and isinstance(e.value, ValueError)
    assert e.value.settings == ["tolerance_mm"] and "--" not in str(e.value)
    assert not out.exists()


def test_a_missing_program_raises_the_file_error(tmp_path):
    with pytest.raises(deflex.FileError) as e:
        deflex.Job(program=str(tmp_path / "missing.nc"), stock=STOCK).simulate()
    assert e.value.file == str(tmp_path / "missing.nc") and e.value.line is None


def test_a_bad_machine_raises_the_config_error(tmp_path):
    machine = tmp_path / "m.yaml"
    machine.write_text("stiffness: [\n")
    prog = tmp_path / "p.nc"
    prog.write_text(GOOD)
    with pytest.raises(deflex.ConfigError) as e:
        deflex.Job(program=str(prog), stock=STOCK, machine=str(machine)).simulate()
    assert e.value.file == str(machine)


def test_usage_errors_name_settings_as_job_keywords(tmp_path):
    with pytest.raises(deflex.UsageError) as e:
        prog = tmp_path / "p.nc"
        prog.write_text(GOOD)
        deflex.Job(program=str(prog), stock=STOCK, kt_N_per_mm2=800.0).simulate()
    assert e.value.settings == ["kt_N_per_mm2", "kr_N_per_mm2", "ka_N_per_mm2"]
    assert set(e.value.settings) <= set(deflex.Job.settings_names())


def test_keywords_are_checked_by_type():
    with pytest.raises(TypeError, match="tolerance"):
        deflex.Job(tolerance="0.01")
    with pytest.raises(TypeError, match="tolerance_mm"):
        deflex.Job(tolerance_mm="0.01")


def test_compensate_to_a_file_keeps_nothing_in_memory(tmp_path):
    prog, out = tmp_path / "p.nc", tmp_path / "p_comp.nc"
    prog.write_text(GOOD)
    r = deflex.Job(program=prog, stock=STOCK).compensate(out)
    assert r.output == str(out) and r.program is None and out.read_bytes().startswith(b"%\nO1\n")


def test_a_raising_progress_callable_stops_the_run(tmp_path):
    out = tmp_path / "out.nc"

    def progress(stage, fraction):
        raise ValueError("stop here")

    with pytest.raises(ValueError, match="stop here"):
        deflex.Job(**SAMPLE).compensate(out, progress=progress)
    assert not out.exists()


def test_ctrl_c_stops_the_run_with_keyboard_interrupt(tmp_path):
    """SIGINT while the run holds no GIL: Observer::cancelled() runs Python's
    handler (PyErr_CheckSignals) and the run stops, writing nothing."""
    out = tmp_path / "out.nc"
    started = threading.Event()
    killer = threading.Thread(target=lambda: started.wait(60) and os.kill(os.getpid(), signal.SIGINT))
    killer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            deflex.Job(**SAMPLE).compensate(out, progress=lambda s, f: started.set())
    finally:
        killer.join()
    assert not out.exists()
