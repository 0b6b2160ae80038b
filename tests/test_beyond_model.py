"""A converged state past the model's limit is no answer: the 90 degree robot of Fig. 11
under a growing tip force toward +x bends its base until the tendon would pass the
centre of curvature (r kappa(0) = 1 at F L^2/EI = 50, bench/results/load_paths.md).
Past that load the shooting equations still "converge" on states whose tendon path runs
backwards near the base, with a truncation estimate far above tol; tr.solve must refuse
them and name the tendon.

Independent check: the base curvature kappa(0) = m_y(0) / EI of the state returned,
from its recorded moment, against 1 / r.
"""

from __future__ import annotations

import math
import warnings

import pytest

import tendonrod as tr
from tendonrod.bench.common import FIG11, EI_of, rod_of

P = FIG11
L, EI, R = P["L"], EI_of(P), P["r"]


def _solve(f):
    robot = tr.Robot(rod_of(P), [tr.Tendon(offset=R)])
    scene = tr.Scene(
        robot,
        displacement=[R * math.pi / 2],
        loads=[tr.PointLoad(s=L, force=(f * EI / L**2, 0.0, 0.0))],
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the plausibility check warns about r kappa too
        return tr.solve(scene)


def test_below_the_limit_is_an_answer():
    sol = _solve(45.0)
    assert sol.success and sol.stable is True
    # r kappa(0) = 0.949 < 1 (the plausibility report's figure), from the base moment
    assert R * abs(sol.moment[0][1]) / EI == pytest.approx(0.949, abs=1e-3)


@pytest.mark.parametrize("f", [55.0, 60.0])
def test_past_the_centre_of_curvature_is_refused(f):
    sol = _solve(f)
    assert not sol.success
    assert sol.status == -9  # TR_ENOEQUILIBRIUM: no equilibrium within the model
    assert "tendon 0 would pass the centre of curvature" in sol.message
    assert "at the converged state" in sol.message and "s = 0 m" in sol.message
    # the state returned is past the limit by its own base moment: r kappa(0) > 1
    assert R * abs(sol.moment[0][1]) / EI > 1.0
