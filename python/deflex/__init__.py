"""deflex from Python: compensate milling-tool deflection in G-code programs,
and analyse the predicted surface error with NumPy, pandas and matplotlib.

    import deflex
    job = deflex.Job(program="part.nc", machine="mill3", stock="box:0,0,-20,100,80,0",
                     tolerance_mm=0.01)
    sim = job.simulate()                  # sim.points["surface_error_mm"], sim.summary, sim.error
    comp = job.compensate("part_comp.nc")  # or compensate() for comp.program in memory

deflex.Job                 the settings of a run and its runs (deflex/job.py)
deflex.compliance, forces, stability, cusp_height_mm   the physics as calls (deflex/physics.py)
deflex.Error and its classes               deflex/errors.py

The compiled half is deflex._deflex (python/src/): the library's job API with
the GIL released while it runs.
"""

from .errors import ConfigError, Error, FileError, InputError, InternalError, UsageError
from .job import Job
from .physics import Compliance, Forces, Stability, compliance, cusp_height_mm, forces, stability
from .results import CompensateResult, ErrorFigures, SimulateResult
from ._deflex import data_dir

__all__ = ["Job", "SimulateResult", "CompensateResult", "ErrorFigures", "compliance", "forces", "cusp_height_mm",
           "Compliance", "Forces", "data_dir", "Error", "InputError", "UsageError", "ConfigError", "FileError", "InternalError"]
