"""tendonrod: deflection of tendon-driven continuum robots under external loads
with prescribed tendon displacements (or tensions).

- :mod:`tendonrod.analytic` -- the paper's closed-form small-deflection formulas
  as NumPy ufuncs (Sections II-III).
- :func:`tendonrod.solve` -- a geometrically exact Cosserat-rod/tendon solver
  (Section IV) with prescribed displacements, tendon stretch, pretension, slack;
  :class:`tendonrod.Problem` -- a scene's structure compiled once, solved warm.
- :func:`tendonrod.sweep`, :func:`tendonrod.solve_batch` -- many scenes at once.
- :mod:`tendonrod.plot`, :mod:`tendonrod.paper` (the paper's studies and figures) and
  :mod:`tendonrod.scenefile` are imported on first use; :mod:`tendonrod.bench` holds
  the benchmark suites (``python -m tendonrod bench``).

SI units everywhere, angles in radians.
"""

from . import _core

gsl_version: str = _core.gsl_version
"""Version of the GSL library tendonrod._core was built against."""

__version__ = "0.1.0"

from . import analytic
from .actuation import ActuationResult, actuate
from .batch import BatchResult, solve_batch
from .fit import FitResult, fit
from .linearization import Jacobian
from .model import DistributedLoad, PointLoad, PointMass, Robot, Rod, Scene, Tendon
from .options import Options
from .path import Path, SpecialPoint, path  # the attribute tendonrod.path is this function
from .plausibility import PlausibilityWarning
from .problem import Problem, jacobian
from .results import ConvergenceError, ConvergenceWarning
from .solver import Solution, compliance, solve
from .sweep import SweepResult, sweep  # the attribute tendonrod.sweep is this function

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
]
__all__ += ["sweep", "SweepResult"]
__all__ += ["solve_batch", "BatchResult"]
__all__ += ["path", "Path", "SpecialPoint"]
