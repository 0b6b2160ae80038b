"""The quick verdict's a posteriori check on two grids: where the quick test's a priori
band (2 % of 1 + the load-induced stiffness scale) is too wide to decide, a stable
solution whose smallest eigenvalue lies far beyond the discretisation error estimated
from the quick grid and one of twice its elements is decided without the full test --
and agrees with it."""

from __future__ import annotations

import math
import warnings

import tendonrod as tr
from tendonrod.solution import _compile


def co_contracted():
    """Three stiff tendons (EA = 1e5 N) at 10 mm, the first retracted r pi/2 and the other
    two held at 0 (tensions ~2 kN: a stiffness scale of ~500), out-of-plane tip load
    (bench/solve.py's hardest verdict)."""
    rod = tr.Rod(0.1, 1.04e-3, 210e9, 80e9, kirchhoff=True)
    r = 0.01
    robot = tr.Robot(
        rod, [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=1e5) for i in range(3)]
    )
    return tr.Scene(
        robot,
        displacement=[r * math.pi / 2, 0.0, 0.0],
        loads=[tr.PointLoad(s=0.1, force=(0, 0.5, 0))],
    )


def test_check_decides_the_co_contracted_scene_as_the_full_test_does():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the tendons strain the backbone beyond 2 %
        sol = tr.solve(co_contracted())
        problem = _compile(sol.scene, sol.options)
        steps = max(1, sol.raw["formulation"]["steps"])
        quick = problem.stability(sol.unknowns, steps, quick=True)
        full = problem.stability(sol.unknowns, steps, quick=False)
    # decided by the check (its reason names the two grids), the margin left to the full test
    assert "on 12 and 24 elements" in quick["reason"], quick["reason"]
    assert math.isnan(quick["stability"])
    assert (quick["stable"], quick["index"]) == (full["stable"], full["index"]) == (True, 0)
    # the solve's own verdict is the quick one (the same words), and its margin on request
    # is the full test's
    assert sol.stable is True and "on 12 and 24 elements" in sol.stability_reason
    assert sol.stability == full["stability"]
    # the gap it certifies lies below the full test's margin (~8.8 EI/L)
    gap = float(quick["reason"].split("within ")[1].split(" ")[0])
    assert 0.0 < gap < full["stability"]
