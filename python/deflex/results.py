"""What a run of a job gives back: the points, the figures, summary.json, the
messages, and for a compensation the program written."""

import json
from typing import NamedTuple

__all__ = ["ErrorFigures", "SimulateResult", "CompensateResult"]


class ErrorFigures(NamedTuple):
    """The predicted surface error over the CL points in material
    (report/stats.hpp). e > 0: material left (undercut); e < 0: dug in."""

    points: int
    max_abs_mm: float
    rms_mm: float
    share_outside: float  # of the points outside +-tolerance, 0..1
    max_under_mm: float   # largest e, >= 0
    max_over_mm: float    # smallest e, <= 0


class SimulateResult:
    """The result of ``Job.simulate()``.

    points       dict of NumPy arrays, one per column of points.csv, named as
                 its header (x_mm, surface_error_mm, ...): one entry per CL
                 point reported. ``line`` is int64, ``normal_source`` an object
                 array of str, the rest float64 (NaN where the CSV is empty).
                 None when the run was asked for no rows.
    summary      summary.json as a dict
    error        ErrorFigures of the points against the design
    figures      the run's loads: peak_force_N, mean_force_N,
                 peak_deflection_mm, peak_mrr_mm3_per_s, cusp_max_mm, cusp_mean_mm
    tolerance_mm the tolerance the run used
    messages     the notes and warnings the run printed (compiler style)
    """

    def __init__(self, raw):
        self.points = raw["points"]
        self.summary = json.loads(raw["summary_json"])
        figures = dict(raw["figures"])
        self.error = ErrorFigures(**figures.pop("error"))
        self._as_written = ErrorFigures(**figures.pop("error_as_written"))
        self.figures = figures
        self.tolerance_mm = raw["tolerance_mm"]
        self.messages = raw["messages"]

    def to_dataframe(self):
        """The points as a pandas DataFrame (pandas is needed only here)."""
        import pandas
        frame = pandas.DataFrame(self.points)
        frame["normal_source"] = frame["normal_source"].astype("category")
        return frame

    def __repr__(self):
        e = self.error
        return (f"<{type(self).__name__}: {e.points} CL points, max {e.max_abs_mm:.4f} mm, "
                f"rms {e.rms_mm:.4f} mm, {100 * e.share_outside:.1f}% outside +-{self.tolerance_mm:g} mm>")


class CompensateResult(SimulateResult):
    """The result of ``Job.compensate()``: as SimulateResult, the points being
    the compensated program's (``surface_error_as_written_mm`` beside them), and

    error_as_written  ErrorFigures of the program as written
    program           the compensated program as str (output=None), else None;
                      decoded as UTF-8 with surrogateescape, so
                      ``program.encode("utf-8", "surrogateescape")`` gives its bytes
    program_bytes     the same as bytes
    output            the file written (output given), else None
    """

    def __init__(self, raw):
        super().__init__(raw)
        self.error_as_written = self._as_written
        self.program_bytes = raw["program"]
        self.program = None if raw["program"] is None else raw["program"].decode("utf-8", "surrogateescape")
        self.output = raw["output"]
