"""The stress suite's plausibility group: scenes that are legal but probably slips (issue
13's list) must solve or build as given and warn, once, naming the quantity and its
value; sensible scenes (the paper's) must stay silent; a 1,000-point sweep of an
implausible scene warns once per rule, not per point; every entry point finds the same.

Each case is a runner (``StressCase.ramp``) returning the suite's record: ``converged``
(what was built or solved did), ``verified`` (the warnings are exactly the expected
ones, each with its value checked against an independent answer), ``message``."""

from __future__ import annotations

import math
import time
import warnings

import numpy as np

from ..model import PointLoad, Robot, Rod, Scene, Tendon
from ..plausibility import PlausibilityWarning
from ..problem import Problem
from ..results import ConvergenceWarning
from ..solver import solve

__all__ = ["plausibility_cases"]

# The NiTi wire of the plausibility rules: L = 0.25 m, d = 1.2 mm, E = 60 GPa, G = 23 GPa.
_L, _D, _E, _G = 0.25, 1.2e-3, 60e9, 23e9


def _wire(kirchhoff=False):
    return Rod(_L, _D, _E, _G, kirchhoff=kirchhoff)


def _record(t0, ok, checks, texts, nit=0):
    """The suite's record from the checks [(passed, what)] and the warnings' texts."""
    bad = [what for passed, what in checks if not passed]
    said = " | ".join(t[:160] for t in texts) or "no warning"
    return dict(
        converged=ok,
        verified=ok and not bad,
        iterations=nit,
        seconds=time.perf_counter() - t0,
        message=("NOT: " + "; ".join(bad) + " | " if bad else "") + said,
    )


def _run(make):
    """``make()`` with the plausibility warnings recorded (convergence warnings off):
    (its result, the texts of the warnings, their findings)."""
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always", PlausibilityWarning)
        warnings.simplefilter("ignore", ConvergenceWarning)
        out = make()
    ws = [w for w in rec if issubclass(w.category, PlausibilityWarning)]
    return out, [str(w.message) for w in ws], [w.message.finding for w in ws]


def _expect(make, rules, value=None, rel=1e-6):
    """A runner: ``make()`` must give exactly one warning per rule in ``rules`` (each
    naming its value), the first one's value ``value`` to ``rel`` when given."""

    def run():
        t0 = time.perf_counter()
        out, texts, found = _run(make)
        ok = getattr(out, "success", True)
        got = sorted(f.rule for f in found if f is not None)
        checks = [(got == sorted(rules), f"warned {got}, expected {sorted(rules)}")]
        if value is not None and found and found[0] is not None:
            v = found[0].value
            checks.append((abs(v - value) <= rel * abs(value), f"value {v!r} != {value!r}"))
        # the warning is the finding's sentence (quantity, value, limit, slip)
        checks.append((all(f.message in t for f, t in zip(found, texts)), "text is the finding's"))
        return _record(t0, bool(ok), checks, texts, getattr(out, "nit", 0))

    return run


def _silent(make):
    """A runner: ``make()`` must succeed without a plausibility warning."""

    def run():
        t0 = time.perf_counter()
        out, texts, _ = _run(make)
        ok = all(getattr(o, "success", True) for o in (out if isinstance(out, list) else [out]))
        return _record(t0, ok, [(not texts, "a sensible scene warned")], texts)

    return run


def _circle(deg, rod=None, r=0.005):
    """A lone tendon under a prescribed tension: a circle of ``deg`` degrees."""
    rod = rod or _wire(kirchhoff=True)
    tau = math.radians(deg) * rod.bending_stiffness / (r * rod.length)
    return Scene(Robot(rod, [Tendon(offset=r)]), tension=[tau])


def _flood():
    """1,000 points, all curled beyond 360 deg: one warning per rule for the sweep, the
    batch and a Problem's loop (a Problem warns once per rule for its life)."""
    from ..batch import solve_batch
    from ..sweeps import sweep

    t0 = time.perf_counter()
    base = _circle(400.0)
    taus = base.tension[0] * np.linspace(1.0, 1.1, 1000)
    res, texts, _ = _run(lambda: sweep(base, {"tension[0]": taus}, progress=False))
    bat, tb, _ = _run(lambda: solve_batch(base, tension=taus[:, None]))
    prob = Problem(base)
    _, tp, _ = _run(lambda: [prob.solve(Scene(base.robot, tension=[t])) for t in taus[:100]])
    checks = [
        (len(texts) == 2 and all("1000 of 1000 points" in t for t in texts), "sweep: 2 warnings"),
        (len(tb) == 2, f"solve_batch: {len(tb)} warnings"),
        (len(tp) == 2, f"Problem: {len(tp)} warnings over 100 solves"),
        (all(len(p) == 2 for p in res.plausibility), "every point's findings kept"),
    ]
    ok = bool(np.all(res.success) and np.all(bat.success))
    return _record(t0, ok, checks, texts)


def _agree():
    """tr.solve, Problem.solve, solve_batch and sweep find the same on a ramp through
    360 deg of curl (tension-controlled: the same solution at every entry point)."""
    from ..batch import solve_batch
    from ..sweeps import sweep, tip_measure

    t0 = time.perf_counter()
    base = _circle(330.0)
    taus = base.tension[0] * np.linspace(1.0, 1.2, 9)
    scenes = [Scene(base.robot, tension=[t]) for t in taus]

    def agree(a, b):
        # the values (a curl in rad, a gap in m) of solutions that agree to the solver's
        # tolerance, 1e-10 of L in position: within 1e-9
        return [(f.rule, f.subject) for f in a] == [(f.rule, f.subject) for f in b] and all(
            abs(f.value - g.value) <= 1e-9 for f, g in zip(a, b)
        )

    one = _run(lambda: [solve(s).plausibility for s in scenes])[0]
    prob = Problem(base)
    pro = _run(lambda: [prob.solve(s).plausibility for s in scenes])[0]
    bat = _run(lambda: solve_batch(base, tension=taus[:, None]).plausibility)[0]
    swp = _run(lambda: sweep(base, {"tension[0]": taus}, progress=False).plausibility)[0]
    per = _run(
        lambda: (
            sweep(
                base, {"tension[0]": taus}, measure=lambda s, x: tip_measure(s, x), progress=False
            ).plausibility
        )
    )[0]
    same = all(agree(one[k], other[k]) for other in (pro, bat, swp, per) for k in range(len(taus)))
    both = any(one) and not all(one)
    return _record(t0, True, [(same, "entry points disagree"), (both, "no straddle")], [])


def plausibility_cases(StressCase) -> list:
    """The group's cases (``StressCase`` passed in: the suite's record type)."""
    wire, kir = _wire(), _wire(kirchhoff=True)
    EA, EI = wire.axial_stiffness, kir.bending_stiffness
    r = 0.005
    cases = [
        # 2.6 kN on the 1.2 mm wire, as tension: axial strain 2600 / EA = 3.83 % (exact)
        (
            "strain/2.6kN-on-1.2mm-wire",
            _expect(
                lambda: solve(
                    Scene(Robot(wire, []), loads=[PointLoad(s=_L, force=(0, 0, 2600.0))])
                ),
                ["strain"],
                2600.0 / EA,
                1e-9,
            ),
        ),
        # the same on a Kirchhoff wire: the strain its section would take
        (
            "strain/kirchhoff-implied",
            _expect(
                lambda: solve(Scene(Robot(kir, []), loads=[PointLoad(s=_L, force=(0, 0, 2600.0))])),
                ["strain"],
                2600.0 / EA,
                1e-9,
            ),
        ),
        # a 1,440 deg curl: a circle (constant curvature, the bending angle is exact)
        (
            "curl/1440deg",
            _expect(
                lambda: solve(_circle(1440.0)),
                ["curl", "self-intersection"],
                math.radians(1440.0),
                1e-9,
            ),
        ),
        (
            "offset/0.5m-on-0.25m-rod",
            _expect(lambda: Robot(wire, [Tendon(offset=0.5)]), ["offset"], 2.0, 1e-12),
        ),
        (
            "angle/90-meant-as-degrees",
            _expect(lambda: Tendon(offset=r, angle=90), ["angle"], 90.0, 0.0),
        ),
        (
            "slenderness/L/d=5",
            _expect(lambda: Rod(5 * _D, _D, _E, _G), ["slenderness"], 5.0, 1e-12),
        ),
        # a lone tendon at a free tip: r kappa = tau r^2 / EI exactly
        (
            "tension/0.95EI/r^2",
            _expect(
                lambda: solve(
                    Scene(Robot(kir, [Tendon(offset=r, end=0.02)]), tension=[0.95 * EI / r**2])
                ),
                ["tension"],
                0.95,
                1e-9,
            ),
        ),
        ("silent/fig11c-antagonistic-127N", _silent(_fig11c)),
        ("silent/readme-fig17-ramp", _silent(_readme_ramp)),
        ("flood/sweep-batch-problem-1000-points", _flood),
        ("entry-points-agree", _agree),
    ]
    return [
        StressCase(
            f"plausibility/{name}",
            "plausibility warnings",
            None,
            ramp=run,
            quick=name.startswith(("strain/2.6", "tension", "silent/fig11c", "entry")),
        )
        for name, run in cases
    ]


def _fig11c():
    """The paper's Fig. 11(c): tendons pulling against each other near EI/r^2."""
    from ..paper import studies

    d = studies.out_of_plane_comparison()
    return [type("Done", (), {"success": bool(d[("success", 50e3)])})()]


def _readme_ramp():
    """The README's robot (Fig. 17) from 0 to 2 P_c, warm along the ramp."""
    rod = Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True)
    robot = Robot(rod, [Tendon(offset=0.01)])
    prob = Problem(Scene(robot, displacement=[0.0157], loads=[PointLoad(s=0.2)]))
    return [
        prob.solve(Scene(robot, displacement=[0.0157], loads=[PointLoad(s=0.2, force=(0, 0, -f))]))
        for f in np.linspace(0.0, 0.7, 15)
    ]
