"""Natural frequencies and mode shapes of small vibrations about an equilibrium:
:func:`modes` and its result :class:`Modes`.

The stiffness is the second variation of the total potential energy that the stability
verdict assembles in C (``csrc/tr_stab_energy.c``): rod strain energy, the
displacement-held tendons as constraints (inextensible) or springs ``EA / l``, the
tension-held ones as constant forces, gravity and the external loads.  The mass is the
rod's (``Rod(density=)``: ``rho A`` on the centre line, ``rho I`` about the section's
axes and ``rho J = 2 rho I`` in torsion, round section) plus the point masses
(:class:`~tendonrod.PointMass`, spacer disks).  The eigenproblem
``K x = omega^2 M x`` is solved in C (``csrc/tr_modes.c``) on three grids of halved
elements and extrapolated; the design and its accuracy are in ``docs/guide/modes.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import _core
from ._fields import _int_option, _option_dict
from .compiled import _compile
from .loads import PointMass
from .mounting import base_pose, points_out, vectors_out
from .results import report_failure

__all__ = ["modes", "Modes"]

# the arrays of a saved result, and the tag of its file format
_ARRAYS = (
    "frequencies",
    "omega2",
    "accuracy",
    "s",
    "position",
    "shape_position",
    "shape_rotation",
    "modal_mass",
    "grid_omega2",
)
_FORMAT = "tendonrod.Modes 1"

# the keys of ``options``: coarsest grid's elements, grids, rotary inertia
_DEFAULTS = {"elements": 24, "levels": 3, "rotary_inertia": True}


@dataclass(frozen=True, eq=False)
class Modes:
    """The vibration modes of an equilibrium (:func:`modes`).

    Attributes
    ----------
    frequencies : ndarray (n,)
        Natural frequencies f = omega / (2 pi) [Hz], ascending.  Float; complex (purely
        imaginary entries for the negative eigenvalues) only for an unstable equilibrium
        computed with ``allow_unstable=True``.
    omega2 : ndarray (n,)
        The eigenvalues omega^2 [rad^2/s^2] of ``K x = omega^2 M x`` (negative: unstable).
    accuracy : ndarray (n,)
        Estimated relative error of each frequency [-] (from the grids: the difference of
        the last two Richardson extrapolations, or the finest grid's change where the
        grids are not yet in their asymptotic range).
    s : ndarray (ns,)
        Arc lengths of the shape samples [m] (the finest grid's nodes, base at 0).
    position : ndarray (ns, 3)
        The equilibrium's centre line there, world frame [m].
    shape_position : ndarray (n, ns, 3)
        Each mode's centre-line displacement, world frame [m], normalised so that the
        largest of ``|shape_position|`` and ``L |shape_rotation|`` over the samples is
        1 m, the entry of largest magnitude positive.
    shape_rotation : ndarray (n, ns, 3)
        Each mode's section rotation, world-frame rotation vectors [rad], the same scale.
    modal_mass : ndarray (n,)
        ``x^T M x`` of each normalised shape [kg]: its kinetic energy is
        ``modal_mass * qdot^2 / 2`` for the amplitude q [m].
    damping_ratio : ndarray (n,) or None
        With ``Rod(damping=eta)`` (Kelvin-Voigt retardation time [s]): ``eta omega / 2``
        per mode, the stiffness-proportional damping of the second variation (exact for
        an unloaded rod; loads and tensions add stiffness that does not dissipate, which
        this overstates).  None without damping.
    grid_omega2 : ndarray (levels, n)
        The eigenvalue of each grid [rad^2/s^2], coarse first.
    solution : Solution
        The equilibrium.
    success, status, message, nit, nfev
        As every result (:class:`~tendonrod.Result`): ``nit`` subspace sweeps, ``nfev``
        factorisations of ``K - sigma M``.

    Examples
    --------
    The torsional mode of a round steel rod, omega = (pi / 2L) sqrt(G / rho):

    >>> rod = tr.Rod(0.2, 1e-2, 207e9, 79.6e9, density=7800.0)
    >>> m = tr.modes(tr.Scene(tr.Robot(rod, [])), n=8)
    >>> k = int(np.argmax(np.abs(m.shape_rotation[:, -1, 2])))  # the twisting one
    >>> bool(abs(2 * np.pi * m.frequencies[k] / (np.pi / 0.4 * np.sqrt(79.6e9 / 7800)) - 1) < 1e-6)
    True
    >>> m.shape_position.shape, bool(m.accuracy[k] < 1e-6)
    ((8, 97, 3), True)
    """

    frequencies: NDArray[Any]
    omega2: NDArray[np.float64]
    accuracy: NDArray[np.float64]
    s: NDArray[np.float64]
    position: NDArray[np.float64]
    shape_position: NDArray[np.float64]
    shape_rotation: NDArray[np.float64]
    modal_mass: NDArray[np.float64]
    damping_ratio: NDArray[np.float64] | None
    grid_omega2: NDArray[np.float64]
    solution: Any = field(repr=False)
    success: bool = False
    status: int = 0
    message: str = ""
    nit: int = -1
    nfev: int = -1

    def save(self, path) -> None:
        """Write the result to ``path`` (``.npz``): every array and the verdict, not the
        solution (save that with :meth:`Solution.save`).  Read back with :meth:`load`."""
        arrays = {name: getattr(self, name) for name in _ARRAYS}
        if self.damping_ratio is not None:
            arrays["damping_ratio"] = self.damping_ratio
        meta = np.array([self.success, self.status, self.nit, self.nfev], dtype=np.int64)
        np.savez(
            path, format=np.array(_FORMAT), meta=meta, message=np.array(self.message), **arrays
        )

    @classmethod
    def load(cls, path) -> Modes:
        """The result written by :meth:`save` (its ``solution`` None).  ValueError for a
        file of another kind."""
        with np.load(path, allow_pickle=False) as f:
            if "format" not in f or str(f["format"]) != _FORMAT:
                raise ValueError(f"Modes.load: {path!r} is not a file written by Modes.save")
            meta = f["meta"]
            return cls(
                **{name: f[name] for name in _ARRAYS},
                damping_ratio=f["damping_ratio"] if "damping_ratio" in f else None,
                solution=None,
                success=bool(meta[0]),
                status=int(meta[1]),
                message=str(f["message"]),
                nit=int(meta[2]),
                nfev=int(meta[3]),
            )

    @property
    def n(self) -> int:
        """The number of modes."""
        return len(self.omega2)

    def __repr__(self) -> str:
        if not self.success:
            return f"Modes(success=False, status={self.status}, message={self.message!r})"
        f = ", ".join(f"{x:.6g}" for x in np.atleast_1d(self.frequencies))
        acc = float(np.nanmax(self.accuracy)) if self.n else math.nan
        return (
            f"Modes(n={self.n}, frequencies=[{f}] Hz, accuracy <= {acc:.1e}, "
            f"samples={len(self.s)}, success=True)"
        )


def _options(options) -> dict:
    opt = _option_dict("modes", options, _DEFAULTS)
    _int_option("modes", opt, "elements", 2, 4096)
    _int_option("modes", opt, "levels", 1, 5)
    if not isinstance(opt["rotary_inertia"], (bool, np.bool_)):
        raise ValueError(
            f"modes: options['rotary_inertia'] must be True or False, got {opt['rotary_inertia']!r}"
        )
    return opt


def _section_mass(rod) -> tuple[float, float, float]:
    """(rho A [kg/m], rho I [kg m], rho J [kg m]) of a round section."""
    if rod.density is None or rod.diameter is None:
        return 0.0, 0.0, 0.0
    d = rod.diameter
    rI = rod.density * math.pi * d**4 / 64.0
    return rod.mass_per_length, rI, 2.0 * rI


def _mass_table(rod) -> np.ndarray:
    """(nmass, 5) rows [s_end, rho A, rho I, rho I, rho J] per section, base first."""
    parts = rod.segments if rod.segments else (rod,)
    rows, end = [], 0.0
    for k, part in enumerate(parts):
        end = rod.length if k == len(parts) - 1 else end + part.length
        rA, rI, rJ = _section_mass(part if rod.segments else rod)
        if rod.segments and part.density is None:
            rA, rI, rJ = _section_mass(rod)
        rows.append([end, rA, rI, rI, rJ])
    return np.array(rows, dtype=float)


def _refusal(sol, status: int, message: str, n: int) -> Modes:
    nan = np.full(n, math.nan)
    return Modes(
        frequencies=nan,
        omega2=nan,
        accuracy=nan,
        s=np.zeros(0),
        position=np.zeros((0, 3)),
        shape_position=np.zeros((n, 0, 3)),
        shape_rotation=np.zeros((n, 0, 3)),
        modal_mass=nan,
        damping_ratio=None,
        grid_omega2=np.zeros((0, n)),
        solution=sol,
        success=False,
        status=status,
        message=message,
    )


def modes(
    scene_or_solution,
    n: int = 6,
    *,
    options: dict | None = None,
    strict: bool = False,
    allow_unstable: bool = False,
) -> Modes:
    """The ``n`` lowest natural frequencies and mode shapes about an equilibrium.

    Parameters
    ----------
    scene_or_solution : Scene or Solution
        The equilibrium: a :class:`~tendonrod.Solution`, or a scene, solved first
        (:func:`~tendonrod.solve` with default options).  The rod needs a mass
        (``Rod(density=...)``, which needs ``diameter``: the rotary inertia is the round
        section's); :class:`~tendonrod.PointMass` loads (spacer disks) add theirs.
    n : int
        Modes wanted, 1 to 64 (default 6).
    options : dict, optional
        ``elements`` (default 24): elements of the coarsest grid, 2 to 4096, spread over
        the pieces between breakpoints; ``levels`` (default 3): grids of halved elements,
        1 to 5 (two or more give the accuracy estimate); ``rotary_inertia`` (default
        True): False drops the sections' rotary inertia (an Euler-Bernoulli beam's mass).
    strict : bool
        Raise :class:`~tendonrod.ConvergenceError` instead of warning when not successful.
    allow_unstable : bool
        An unstable equilibrium has no vibration modes and is refused with the stability
        verdict's reason; True computes them anyway (negative omega^2: imaginary
        frequencies, the growth rates of the unstable directions).

    Returns
    -------
    Modes
        Frequencies [Hz], shapes, modal masses, accuracy estimates; ``success``.

    Raises
    ------
    ValueError
        ``n`` or ``options`` out of range, a rod without density.

    Notes
    -----
    Small vibrations about the equilibrium: a slack tendon stays slack, a taut one taut;
    one at its taut/slack switch vibrates as slack (the message names it).  Point masses
    carry no rotary inertia.
    Channel friction is refused (the static friction state is not an energy; sticking
    tendons would be a different model).  A world-fixed point moment is refused as by
    the stability verdict (not conservative).

    Examples
    --------
    >>> rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0, kirchhoff=True)
    >>> m = tr.modes(tr.Scene(tr.Robot(rod, [])), n=2, options={"rotary_inertia": False})
    >>> beta_L = (m.omega2 * rod.mass_per_length * 0.2**4 / rod.bending_stiffness) ** 0.25
    >>> np.round(beta_L, 6)  # Euler-Bernoulli: 1.875104 in both planes
    array([1.875104, 1.875104])
    """
    from .solution import Solution
    from .solver import solve

    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= 64:
        raise ValueError(f"modes: n must be an int in [1, 64], got {n!r}")
    n = int(n)
    opt = _options(options)
    sol = scene_or_solution
    if not isinstance(sol, Solution):
        from .model import Scene

        if not isinstance(sol, Scene):
            raise TypeError(
                f"modes: scene_or_solution must be a Scene or a Solution, got {type(sol).__name__}"
            )
        sol = solve(sol, strict=strict)
    scene = sol.scene
    rod = scene.robot.rod
    mass = _mass_table(rod)
    if not np.all(mass[:, 1] > 0.0):
        raise ValueError(
            f"modes: the rod has no mass: give Rod(density=...) with a diameter "
            f"(density={rod.density!r}, diameter={rod.diameter!r})"
        )
    pm = np.array(
        [[ld.s, ld.mass] for ld in scene.loads if isinstance(ld, PointMass)], dtype=float
    ).reshape(-1, 2)
    result = None
    if not sol.success or sol.unknowns is None:
        result = _refusal(sol, -1, f"no equilibrium: {sol.message}", n)
    elif any(t.friction > 0.0 for t in scene.robot.tendons):
        result = _refusal(
            sol,
            -1,
            "not computed: channel friction holds the tendons in a static friction state, "
            "which is not an energy; solve the frictionless scene (friction=0) for its modes",
            n,
        )
    elif sol.stability_reason.startswith("not tested: a point moment"):
        result = _refusal(sol, -1, f"not computed: {sol.stability_reason}", n)
    elif sol.stable is False and not allow_unstable:
        result = _refusal(
            sol,
            _core.STATUS_UNSTABLE,
            f"the equilibrium is unstable and has no vibration modes ({sol.stability_reason}); "
            f"allow_unstable=True gives the imaginary frequencies of its unstable directions",
            n,
        )
    if result is not None:
        report_failure(result, strict, f"modes: {result.message}")
        return result
    steps = max(1, int(sol.raw["formulation"]["steps"]))
    unknowns = sol.unknowns
    assert unknowns is not None  # refused above
    raw = _core.modes(
        _compile(scene, sol.options),
        unknowns,
        steps,
        n,
        mass,
        pm,
        elements=int(opt["elements"]),
        levels=int(opt["levels"]),
        rotary=bool(opt["rotary_inertia"]),
    )
    if raw["status"] != 0:
        result = _refusal(sol, raw["status"], f"modes: {raw['message']}", n)
        report_failure(result, strict, result.message)
        return result
    w2 = raw["omega2"]
    freq = (
        np.sqrt(w2.astype(complex)) / (2 * math.pi)
        if np.any(w2 < 0)
        else np.sqrt(w2) / (2 * math.pi)
    )
    acc = 0.5 * raw["error"] / np.abs(w2)
    pose = base_pose(scene.robot)
    eta = getattr(rod, "damping", None)
    message = raw["message"]
    if sol.stable is None:
        message += f"; the stability verdict: {sol.stability_reason}"
    tau, slack = np.ravel(sol.raw["tension"]), np.ravel(sol.raw["slack"])
    held = [] if scene.displacement is None else list(scene.displacement)
    switch = [
        i for i, ctl in enumerate(held) if ctl is not None and tau[i] == 0.0 and slack[i] == 0.0
    ]
    if switch:
        message += (
            f"; tendon(s) {switch} at their taut/slack switch vibrate as slack (about a "
            f"switch the vibration is not linear)"
        )
    return Modes(
        frequencies=freq,
        omega2=w2,
        accuracy=acc,
        s=raw["s"],
        position=points_out(pose, raw["position"]),
        shape_position=vectors_out(pose, raw["dpos"]),
        shape_rotation=vectors_out(pose, raw["drot"]),
        modal_mass=raw["modal_mass"],
        damping_ratio=None if not eta else 0.5 * eta * np.sqrt(np.abs(w2)),
        grid_omega2=raw["levels"],
        solution=sol,
        success=True,
        status=0,
        message=message,
        nit=raw["nit"],
        nfev=raw["nfac"],
    )
