"""The physics as plain calls: compliance C(h) (`deflex stiffness`), cutting
forces over a revolution (`deflex forces`), the cusp height of ball-end passes
(process/cusp.hpp). Lengths mm, forces N, compliance mm/N, angles degrees."""

from typing import NamedTuple

from . import _deflex

__all__ = ["Compliance", "Forces", "Stability", "compliance", "forces", "stability", "cusp_height_mm"]


class Compliance(NamedTuple):
    heights_mm: "numpy.ndarray"       # (n,) load heights above the tip
    matrix_mm_per_N: "numpy.ndarray"  # (n, 3, 3): rows displacement x, y, z; columns force x, y, z; machine axes


class Forces(NamedTuple):
    angle_deg: "numpy.ndarray"   # (steps,) rotation of tooth 1's tip
    force_N: "numpy.ndarray"     # (steps, 3) Fx, Fy, Fz on the tool, machine axes (feed +X, M3, Z up)
    mean_N: "numpy.ndarray"      # (3,) over the revolution
    peak_abs_N: "numpy.ndarray"  # (3,) largest |F| per axis
    shape_code: "str | None"     # Morelli's code of the curve (flat end, down-milling), else None


class Stability(NamedTuple):
    rpm: "numpy.ndarray"          # (points + 1,) spindle speeds
    ap_limit_mm: "numpy.ndarray"  # (points + 1,) the largest stable a_p at each (the lobes' lower envelope)
    pockets: "numpy.ndarray"      # (n, 2) rpm, ap_limit_mm of the envelope's peaks, best first
    ap_min_mm: float              # the absolute limit, stable at every speed
    ap_min_chatter_Hz: float
    modes: list                   # the model's tip modes: dicts of frequency_Hz, damping_ratio, stiffness_N_per_mm
    frf_source: str


def compliance(tool, tool_file=None, machine=None, heights_mm=None, tool_only=False, method="beam", mesh_mm=0.0):
    """C(h) of a tool of the library (default: config.yaml's tool_file, else
    the installed samples/tools.yaml) in its holder on `machine` (a name or a
    profile .yaml; None or tool_only: clamped rigidly at the holder face).
    heights_mm: load heights along the flutes (default seven, tip to flute
    end). method: "beam" (Timoshenko beam) or "solid" (gmsh + FEM, mesh_mm)."""
    d = _deflex.compliance(tool, tool_file, machine, None if heights_mm is None else list(heights_mm),
                           tool_only, method, mesh_mm)
    return Compliance(d["heights_mm"], d["matrix_mm_per_N"])


def forces(*, tool, ae_mm, ap_mm, fz_mm, milling="down", tool_file=None, material=None, material_file=None,
           kt_N_per_mm2=None, kr_N_per_mm2=None, ka_N_per_mm2=None, kte_N_per_mm=None, kre_N_per_mm=None,
           kae_N_per_mm=None, steps=360, dz_mm=0.05):
    """Cutting forces over one spindle revolution for a straight cut along +X
    into a wall (mechanistic model, Altintas 2012 ch. 2): a_e from the cutting
    side (>= D: a slot), a_p above the tip, f_z per tooth; milling "down" or
    "up". The material by name (default config.yaml's) or by its coefficients."""
    d = _deflex.forces(tool=tool, tool_file=tool_file, material=material, material_file=material_file,
                       kt_N_per_mm2=kt_N_per_mm2, kr_N_per_mm2=kr_N_per_mm2, ka_N_per_mm2=ka_N_per_mm2,
                       kte_N_per_mm=kte_N_per_mm, kre_N_per_mm=kre_N_per_mm, kae_N_per_mm=kae_N_per_mm,
                       ae_mm=ae_mm, ap_mm=ap_mm, fz_mm=fz_mm, milling=milling, steps=steps, dz_mm=dz_mm)
    return Forces(d["angle_deg"], d["force_N"], d["mean_N"], d["peak_abs_N"], d.get("shape_code"))


def stability(*, tool, ae_mm, ap_mm=None, milling="down", machine=None, frf=None, tool_only=False, rpm=None,
              points=1000, tool_file=None, material=None, material_file=None):
    """The zero-order stability limit (chatter, Altintas & Budak 1995) against
    spindle speed, as `deflex stability`: from the beam model's tip modes on
    `machine` (default config.yaml's; tool_only: clamped at the holder face) or
    a measured FRF CSV (`frf`, then give rpm=(min, max) without a machine).
    a_e from the cutting side; ap_mm: the engagement of that depth on the
    tool's own shape (default: the straight wall's immersion)."""
    d = _deflex.stability(tool=tool, tool_file=tool_file, material=material, material_file=material_file,
                          machine=machine, frf=frf, tool_only=tool_only, ae_mm=ae_mm, ap_mm=ap_mm, milling=milling,
                          rpm=rpm, points=points)
    return Stability(d["limit"][:, 0], d["limit"][:, 1], d["pockets"], d["ap_min_mm"], d["ap_min_chatter_Hz"],
                     d["modes"], d["frf_source"])


def cusp_height_mm(diameter_mm, stepover_mm, inclination_deg=0.0, direction_deg=0.0):
    """The cusp between neighbouring ball-end passes (Miko et al. Eq. 4 and 7):
    ball diameter, horizontal step-over across the feed, the surface's
    inclination alpha_1 and the angle A between feed and fall line (0: up or
    down the slope, 90: along a level line). Scalars or NumPy arrays (broadcast)."""
    return _deflex.cusp_height_mm(diameter_mm, stepover_mm, inclination_deg, direction_deg)
