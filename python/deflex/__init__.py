"""deflex from Python: compensate milling-tool deflection in G-code programs,
and analyse the predicted surface error with NumPy, pandas and matplotlib.

    import deflex
    job = deflex.Job(program="part.nc", machine="mill3", stock="box:0,0,-20,100,80,0",
                     tolerance_mm=0.01)
    sim = job.simulate()                  # sim.points["surface_error_mm"], sim.summary, sim.error
    comp = job.compensate("part_comp.nc")  # or compensate() for comp.program in memory

deflex.Job                 the settings of a run and its runs (deflex/job.py)
deflex.compliance, forces, cusp_height_mm   the physics as calls (deflex/physics.py)
deflex.Error and its classes               deflex/errors.py

The compiled half is deflex._deflex (python/src/): the library's job API with
the GIL released while it runs.
"""

import os as _os
import pathlib as _pathlib

# deflex finds its data (config.yaml, the sample machines and libraries) beside
# the running binary (profile/search.hpp), which for Python is the interpreter:
# an installed package points it at its own prefix's share/deflex instead
# (<prefix>/lib/python3/dist-packages/deflex -> <prefix>/share/deflex).
_up = _pathlib.Path(__file__).resolve().parents
if "DEFLEX_DATA_DIR" not in _os.environ and len(_up) > 4 and (_up[4] / "share/deflex/config.yaml").is_file():
    _os.environ["DEFLEX_DATA_DIR"] = str(_up[4] / "share" / "deflex")

from .errors import ConfigError, Error, FileError, InputError, InternalError, UsageError
from .job import Job
from .physics import Compliance, Forces, compliance, cusp_height_mm, forces
from .results import CompensateResult, ErrorFigures, SimulateResult

__all__ = ["Job", "SimulateResult", "CompensateResult", "ErrorFigures", "compliance", "forces", "cusp_height_mm",
           "Compliance", "Forces", "Error", "InputError", "UsageError", "ConfigError", "FileError", "InternalError"]
