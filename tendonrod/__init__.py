"""tendonrod: deflection of tendon-driven continuum robots under external loads
with prescribed tendon displacements (or tensions).

- :mod:`tendonrod.analytic` -- the paper's closed-form small-deflection formulas
  as NumPy ufuncs (Sections II-III).
- :func:`tendonrod.solve` -- a geometrically exact Cosserat-rod/tendon solver
  (Section IV) with prescribed displacements, tendon stretch, pretension, slack.

SI units everywhere, angles in radians.
"""

from . import _core

gsl_version: str = _core.gsl_version
"""Version of the GSL library tendonrod._core was built against."""

__version__ = "0.1.0"

from . import analytic  # noqa: E402

# BEGIN Cosserat solver API (model.py, solver.py)
from .model import (
    DistributedLoad,
    PointLoad,
    Robot,
    Rod,
    Scene,  # noqa: E402
    Tendon,
)
from .solver import (
    ConvergenceError,
    ConvergenceWarning,
    Options,  # noqa: E402
    Solution,
    compliance,
    solve,
)

# END Cosserat solver API
# BEGIN design studies (sweep.py; plot, paper and scenefile are imported on first use)
from .sweep import SweepResult, sweep  # noqa: E402  (tendonrod.sweep is this function)

_LAZY_SUBMODULES = ("plot", "paper", "scenefile")


def __getattr__(name):
    if name in _LAZY_SUBMODULES:
        import importlib

        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module 'tendonrod' has no attribute {name!r}")


# END design studies

# BEGIN batch solves (batch.py, issue 7)
from .batch import BatchResult, solve_batch  # noqa: E402

# END batch solves

__all__ = ["analytic", "gsl_version", "__version__"]
__all__ += [
    "Rod",
    "Tendon",
    "Robot",
    "Scene",
    "PointLoad",
    "DistributedLoad",
    "Options",
    "Solution",
    "solve",
    "compliance",
    "ConvergenceWarning",
    "ConvergenceError",
]
__all__ += ["sweep", "SweepResult"]
__all__ += ["solve_batch", "BatchResult"]
