"""examples/plot_error.py on the sample: it runs and writes a real plot."""

import os
import subprocess
import sys

import matplotlib.image

from conftest import ROOT


def test_plot_error_writes_a_png(tmp_path):
    png = tmp_path / "error.png"
    done = subprocess.run([sys.executable, str(ROOT / "examples" / "plot_error.py"), str(png)], cwd=ROOT,
                          env=dict(os.environ), capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "compensated" in done.stdout
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    image = matplotlib.image.imread(str(png))
    assert image.shape[0] > 400 and image.std() > 0.05  # not a blank canvas
