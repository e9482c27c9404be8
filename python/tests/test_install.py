"""cmake --install puts a package that imports from the installed tree alone
(PYTHONPATH=<prefix>/lib/python3/dist-packages) and finds that prefix's data."""

import os
import pathlib
import subprocess
import sys

import pytest


@pytest.mark.skipif("DEFLEX_BUILD_DIR" not in os.environ, reason="CTest names the build to install")
def test_the_installed_package_imports_and_finds_its_data(tmp_path):
    prefix = tmp_path / "usr"
    subprocess.run(["cmake", "--install", os.environ["DEFLEX_BUILD_DIR"], "--prefix", str(prefix)], check=True,
                   capture_output=True)
    site = prefix / "lib" / "python3" / "dist-packages"
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "DEFLEX_DATA_DIR")}
    env["PYTHONPATH"] = str(site)
    code = ("import deflex, os\n"
            "print(deflex.__file__)\n"
            "print(deflex.data_dir())\n"
            "print(deflex.compliance('T5', machine='mill3', heights_mm=[0]).matrix_mm_per_N[0, 0, 0])\n")
    # From an empty folder: no ./config.yaml, no samples/ beside it.
    work = tmp_path / "work"
    work.mkdir()
    done = subprocess.run([sys.executable, "-c", code], cwd=work, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    module, data, c_xx = done.stdout.splitlines()
    assert pathlib.Path(module).parent == site / "deflex"
    assert pathlib.Path(data) == prefix / "share" / "deflex"
    assert float(c_xx) > 0



def test_the_data_folder_is_one_that_exists_or_none(tmp_path):
    # A folder that does not exist is no data folder (as `deflex --version`
    # says "none found"); one that does is named as it is.
    assert data_dir_with(tmp_path / "missing") is None
    assert data_dir_with(tmp_path) == str(tmp_path)


def data_dir_with(folder):
    """deflex.data_dir() in a fresh interpreter with DEFLEX_DATA_DIR=folder."""
    env = dict(os.environ, DEFLEX_DATA_DIR=str(folder))
    done = subprocess.run([sys.executable, "-c", "import deflex; print(deflex.data_dir())"], env=env,
                          capture_output=True, text=True, check=True)
    out = done.stdout.strip()
    return None if out == "None" else out
