"""tendonrod: deflection of tendon-driven continuum robots under external loads
with prescribed tendon displacements (or tensions).

- :mod:`tendonrod.analytic` -- the paper's closed-form small-deflection formulas
  as NumPy ufuncs (Sections II-III).
- :func:`tendonrod.solve` -- a geometrically exact Cosserat-rod/tendon solver
  (Section IV) with prescribed displacements, tendon stretch, pretension, slack;
  :class:`tendonrod.Problem` -- a scene's structure compiled once, solved warm.
- :func:`tendonrod.sweep` (its module :mod:`tendonrod.sweeps`),
  :func:`tendonrod.solve_batch` -- many scenes at once.
- :func:`tendonrod.path` -- an equilibrium branch (:class:`tendonrod.Branch`) followed
  through limit and bifurcation points (its module :mod:`tendonrod.continuation`).
- Every result carries ``success``, ``status``, ``message``, ``nit``, ``nfev``
  (:class:`tendonrod.Result`); every entry point that can fail warns
  (:class:`ConvergenceWarning`) or, with ``strict=True``, raises
  (:class:`ConvergenceError`).
- :meth:`Solution.save` / :func:`tendonrod.load` -- a solution (or a :class:`Trajectory`) to
  an ``.npz`` file and back.
- :mod:`tendonrod.plot`, :mod:`tendonrod.paper` (the paper's studies and figures) and
  :mod:`tendonrod.scenefile` are imported on first use; :mod:`tendonrod.bench` holds
  the benchmark suites (``python -m tendonrod bench``).

SI units everywhere, angles in radians.
"""

from . import _build_check
from ._version import __version__

_core = _build_check.import_core()

gsl_version: str = _core.gsl_version
"""Version of the GSL library tendonrod._core was built against."""

from . import analytic
from ._io import file_kind as _file_kind
from ._io import read_solution as _read_solution
from ._linearize import jacobian
from .actuation import ActuationResult, actuate
from .batch import BatchResult, solve_batch
from .continuation import Branch, SpecialPoint, path
from .dynamics import Trajectory, simulate, simulation_options
from .fit import FitResult, fit
from .friction import Slip, slip
from .linearization import Jacobian
from .model import DistributedLoad, PointLoad, PointMass, Robot, Rod, Scene, Tendon
from .options import Options
from .plausibility import PlausibilityWarning
from .problem import Problem
from .results import ConvergenceError, ConvergenceWarning, Result
from .solver import Solution, compliance, solve
from .sweeps import ComplianceMeasure, SweepResult, sweep, tip_measure
from .vibration import Modes, modes

__all__ = [
    "__version__",
    "gsl_version",
    "analytic",
    # the scene
    "Rod",
    "Tendon",
    "Robot",
    "Scene",
    "PointLoad",
    "PointMass",
    "DistributedLoad",
    "Options",
    # solving
    "solve",
    "Problem",
    "Solution",
    "load",
    "compliance",
    "jacobian",
    "Jacobian",
    "actuate",
    "ActuationResult",
    "fit",
    "FitResult",
    "slip",
    "Slip",
    # many scenes
    "solve_batch",
    "BatchResult",
    "sweep",
    "SweepResult",
    "tip_measure",
    "ComplianceMeasure",
    "path",
    "Branch",
    "modes",
    "Modes",
    "simulate",
    "simulation_options",
    "Trajectory",
    "SpecialPoint",
    # verdicts
    "Result",
    "ConvergenceWarning",
    "ConvergenceError",
    "PlausibilityWarning",
]


def load(path) -> Solution | Trajectory:
    """Read a :class:`Solution` written by :meth:`Solution.save`, or a :class:`Trajectory`
    written by :meth:`Trajectory.save` (``.npz``): which one, the file says (a trajectory's
    archive holds a ``format`` entry ``"tendonrod.Trajectory <version>"``, a solution's a
    ``__tendonrod__`` header).

    Parameters
    ----------
    path : str or PathLike
        The file.

    Returns
    -------
    Solution or Trajectory
        Equal bit for bit to the one saved: a solution's raw arrays and scalars, scene
        and options; a trajectory's arrays and ``success/status/message/nit/nfev`` (its
        ``final`` state is not saved: a loaded trajectory does not resume a run).  The
        type is the union: check it with ``isinstance`` where it matters (both have
        ``tip_position``, ``success`` and ``message``).

    Raises
    ------
    ValueError
        The file is neither a solution nor a trajectory written by tendonrod (or of
        another format version); the message names the file and what is wrong.
    FileNotFoundError, IsADirectoryError
        ``path`` names no file.

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> import os, tempfile
    >>> sol = tr.solve(tr.Scene(robot, displacement=[0.01]))
    >>> sol.save(path := os.path.join(tempfile.mkdtemp(), "sol.npz"))
    >>> bool((tr.load(path).tip_position == sol.tip_position).all())
    True

    A trajectory comes back as a :class:`Trajectory`:

    >>> rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0)
    >>> traj = tr.simulate(tr.Scene(tr.Robot(rod, [])), 1e-3, 1e-4)
    >>> traj.save(path := os.path.join(tempfile.mkdtemp(), "traj.npz"))
    >>> back = tr.load(path)
    >>> isinstance(back, tr.Trajectory), bool((back.t == traj.t).all())
    (True, True)
    """
    if _file_kind(path) == "Trajectory":
        return Trajectory.load(path)
    return Solution(*_read_solution(path))


_LAZY_SUBMODULES = ("plot", "paper", "scenefile")
# the documented modules, besides the names of __all__ (the implementation's modules are
# importable by name, but not listed)
_PUBLIC_MODULES = _LAZY_SUBMODULES + ("analytic", "routing", "sweeps", "continuation", "bench")
# old names kept for 0.2 (tendonrod._deprecation): old name -> (new spelling, the object)
_DEPRECATED = {"Path": ("tendonrod.Branch", Branch)}


def __getattr__(name):
    """``tendonrod.plot``, ``tendonrod.paper`` and ``tendonrod.scenefile`` on first use
    (they are not needed to solve, and plot and paper reach for matplotlib); the old names
    of ``_DEPRECATED`` with a ``DeprecationWarning``."""
    if name in _LAZY_SUBMODULES:
        import importlib

        return importlib.import_module(f".{name}", __name__)
    if name in _DEPRECATED:
        from ._deprecation import deprecated

        new, obj = _DEPRECATED[name]
        deprecated(f"tendonrod.{name}", new)
        return obj
    raise AttributeError(f"module 'tendonrod' has no attribute {name!r}")


def __dir__():
    """The public names only: ``__all__`` and the documented modules."""
    return sorted(set(__all__) | set(_PUBLIC_MODULES))
