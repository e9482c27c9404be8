"""deflex.Job: the settings of a run (job::Settings, include/deflex/job/settings.hpp)
and its runs."""

from . import _deflex
from .results import CompensateResult, SimulateResult

__all__ = ["Job"]


class Job:
    """A deflex job: what ``deflex compensate`` / ``deflex simulate`` take as options.

    Keywords (None or left out: the default of config.yaml or the machine
    profile, as on the command line; ``Job.settings_names()`` lists them)::

        program, output, reference, report_dir         paths
        machine, dialect, config                       names or .yaml paths
        max_errors, block_delete (bool), strict, max_blocks
        material, material_file,
        kt_N_per_mm2, kr_N_per_mm2, ka_N_per_mm2,      cutting coefficients
        kte_N_per_mm, kre_N_per_mm, kae_N_per_mm       edge coefficients
        part, part_gap_mm                              the design surface
        tool_file, tool, stock ("box:X0,Y0,Z0,X1,Y1,Z1", a solid, a .zmap, "auto[:MARGIN]")
        stock_from      [path, (program, tool_file), ...] earlier programs, in order
        tolerance_mm, gain, feed_limit_N, spindle_rpm, feed_mm_per_min,
        cell_mm, cl_spacing_mm, max_iterations, threads, tool_only, expand_subprograms
        measured, probe_program, measured_reach_mm     measurements of the cut part

    An unknown keyword or a value of the wrong type raises TypeError; a value
    out of range raises deflex.UsageError when the job runs, before anything
    is read or computed.
    """

    def __init__(self, **settings):
        self._job = _deflex.Job(**settings)

    @classmethod
    def from_file(cls, path, **overrides):
        """A job file (YAML, as ``deflex compensate --job``); the keywords
        override it. Paths in it are relative to its folder."""
        job = cls.__new__(cls)
        job._job = _deflex.Job.from_file(path, **overrides)
        return job

    @staticmethod
    def settings_names():
        """The keywords Job takes."""
        return list(_deflex.Job().settings)

    @property
    def settings(self):
        """Every setting by its keyword (None: unset, the default applies)."""
        return self._job.settings

    def simulate(self, progress=None, rows=True):
        """Predicts the surface error of the program (against ``reference``
        when given); with ``report_dir`` writes the report there.

        progress: None or callable(stage: str, fraction: float), called from
        this thread as the run goes; an exception it raises stops the run and
        is raised here. Ctrl-C stops the run with KeyboardInterrupt.
        rows: False keeps no points (``points`` is None), for long programs.
        """
        return SimulateResult(self._job.simulate(progress, rows))

    def compensate(self, output=None, progress=None, rows=True):
        """Compensates the program. output: None keeps the compensated program
        in memory (``result.program``) unless the settings name an output; a
        path writes it there atomically (``result.output``; nothing in memory).
        A run that fails writes nothing. progress, rows: as simulate()."""
        return CompensateResult(self._job.compensate(output, progress, rows))

    def fit(self, output=None, progress=None, determined_within=0.10):
        """Fits the machine profile to the ``measured`` points of the part the
        program cut (docs/fit.md), as ``deflex fit`` does. output: None keeps
        the fitted profile in the result's ``"profile"`` (text); a path writes
        it there atomically. Returns a dict: ``"parameters"`` (per parameter:
        ``fitted``, ``factor`` of the starting value, ``interval95``,
        ``why_held``), ``"features"`` (the residuals per test-cut feature),
        the residual rms and max before and after (mm), ``"profile"``."""
        return self._job.fit(output, progress, determined_within)

    def __repr__(self):
        given = {k: v for k, v in self.settings.items() if v not in (None, "", [], False)}
        return "deflex.Job(" + ", ".join(f"{k}={v!r}" for k, v in given.items()) + ")"
