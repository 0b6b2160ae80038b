"""tendonrod: deflection of tendon-driven continuum robots under external loads
with prescribed tendon displacements (or tensions).

- :mod:`tendonrod.analytic` -- the paper's closed-form small-deflection formulas
  as NumPy ufuncs (Sections II-III).
- :func:`tendonrod.solve` -- a geometrically exact Cosserat-rod/tendon solver
  (Section IV) with prescribed displacements, tendon stretch, pretension, slack;
  :class:`tendonrod.Problem` -- a scene's structure compiled once, solved warm.
- :mod:`tendonrod.sweep` (a module that is also callable: ``tr.sweep(scene, vary)`` is
  :func:`tendonrod.sweep.sweep`), :func:`tendonrod.solve_batch` -- many scenes at once.
- :mod:`tendonrod.path` (callable too: ``tr.path(scene, parameter, span)``) -- an
  equilibrium branch followed through limit and bifurcation points.
- :meth:`Solution.save` / :func:`tendonrod.load` -- a solution to an ``.npz`` file and back.
- :mod:`tendonrod.plot`, :mod:`tendonrod.paper` (the paper's studies and figures) and
  :mod:`tendonrod.scenefile` are imported on first use; :mod:`tendonrod.bench` holds
  the benchmark suites (``python -m tendonrod bench``).

SI units everywhere, angles in radians.
"""

from typing import TYPE_CHECKING

from ._build_check import import_core
from ._version import __version__

_core = import_core()

gsl_version: str = _core.gsl_version
"""Version of the GSL library tendonrod._core was built against."""

from . import analytic
from . import path as _path_mod  # callable: tr.path(...) runs tendonrod.path.path
from . import sweep as _sweep_mod  # callable: tr.sweep(...) runs tendonrod.sweep.sweep
from ._linearize import jacobian
from ._sweep_module import make_callable
from .actuation import ActuationResult, actuate
from .batch import BatchResult, solve_batch
from .fit import FitResult, fit
from .friction import Slip, slip
from .linearization import Jacobian
from .model import DistributedLoad, PointLoad, PointMass, Robot, Rod, Scene, Tendon
from .options import Options
from .path import Path, SpecialPoint
from .plausibility import PlausibilityWarning
from .problem import Problem
from .results import ConvergenceError, ConvergenceWarning, Result
from .solver import Solution, compliance, solve

make_callable(_sweep_mod)
make_callable(_path_mod)
if TYPE_CHECKING:
    # what a type checker sees: tr.sweep and tr.path as the functions they call (their
    # modules stay importable by name: from tendonrod.sweep import OUTCOME_OK)
    from .path import path as path
    from .sweep import sweep as sweep
else:
    path, sweep = _path_mod, _sweep_mod
from ._io import read_solution
from .sweep import ComplianceMeasure, SweepResult, tip_measure


def load(path) -> Solution:
    """Read a :class:`Solution` written by :meth:`Solution.save` (``.npz``).

    Parameters
    ----------
    path : str or PathLike
        The file.

    Returns
    -------
    Solution
        Equal bit for bit to the one saved: its raw arrays and scalars, scene and options.

    Raises
    ------
    ValueError
        The file is not a solution written by tendonrod (or of another format).

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> import os, tempfile
    >>> sol = tr.solve(tr.Scene(robot, displacement=[0.01]))
    >>> sol.save(path := os.path.join(tempfile.mkdtemp(), "sol.npz"))
    >>> bool((tr.load(path).tip_position == sol.tip_position).all())
    True
    """
    return Solution(*read_solution(path))


_LAZY_SUBMODULES = ("plot", "paper", "scenefile")


def __getattr__(name):
    """``tendonrod.plot``, ``tendonrod.paper`` and ``tendonrod.scenefile`` on first use
    (they are not needed to solve, and plot and paper reach for matplotlib)."""
    if name in _LAZY_SUBMODULES:
        import importlib

        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'tendonrod' has no attribute {name!r}")


__all__ = ["analytic", "gsl_version", "__version__"]
__all__ += [
    "Rod",
    "Tendon",
    "Robot",
    "Scene",
    "PointLoad",
    "PointMass",
    "DistributedLoad",
    "Options",
    "Solution",
    "Problem",
    "solve",
    "compliance",
    "jacobian",
    "Jacobian",
    "actuate",
    "ActuationResult",
    "fit",
    "FitResult",
    "ConvergenceWarning",
    "ConvergenceError",
    "PlausibilityWarning",
    "Result",
]
__all__ += ["sweep", "SweepResult", "tip_measure", "ComplianceMeasure", "load"]
__all__ += ["solve_batch", "BatchResult"]
__all__ += ["path", "Path", "SpecialPoint"]
__all__ += ["slip", "Slip"]
