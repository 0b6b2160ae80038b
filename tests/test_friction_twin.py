"""Channel friction has no energy whose minimum decides stability, so a frictional
solve's state is not tested; what the core reports instead is the verdict of its
frictionless twin (the same state and tensions, mu = 0), and a success whose twin is
unstable says so (status TR_FRICTION_HELD, a ConvergenceWarning) instead of passing as
an untested success.  Reproducer: a Nitinol rod with one tendon at 3 mm retracted r pi/3
and a tip load across it buckles out of the plane without friction."""

import math
import warnings

import pytest

import tendonrod as tr
from tendonrod import _core

L = 0.25


def _scene(friction):
    rod = tr.Rod(length=L, diameter=1.2e-3, E=60e9, G=23e9)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.003, EA=1.4e4, friction=friction)])
    return tr.Scene(
        robot, displacement=[0.003 * math.pi / 3], loads=[tr.PointLoad(s=L, force=(-0.3, 0, 0))]
    )


def test_frictionless_scene_is_unstable_in_the_plane():
    # the independent fact the twin must agree with: without friction the planar state
    # is unstable (one negative mode), the stable one is out of the plane
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        sol = tr.solve(_scene(0.0))
    assert not sol.success and sol.stable is False, sol.message


@pytest.mark.parametrize("force_spatial", [False, True])
def test_friction_does_not_hide_the_twin_instability(force_spatial):
    with pytest.warns(tr.ConvergenceWarning, match="frictionless twin"):
        sol = tr.solve(_scene(0.1), options=tr.Options(force_spatial=force_spatial))
    assert sol.success and sol.stable is None
    assert sol.status == _core.STATUS_FRICTION_HELD
    assert "frictionless twin" in sol.stability_reason
    assert "unstable" in sol.stability_reason and "1 negative mode" in sol.stability_reason
    # it says where to look for the state friction may not hold
    assert "friction = 0" in sol.message and "across the bending plane" in sol.message


def test_a_stable_twin_is_reported_without_warning():
    # without the tip load the retracted rod is stable, with friction or not
    rod = tr.Rod(length=L, diameter=1.2e-3, E=60e9, G=23e9)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.003, EA=1.4e4, friction=0.1)])
    with warnings.catch_warnings():
        warnings.simplefilter("error", tr.ConvergenceWarning)
        sol = tr.solve(tr.Scene(robot, displacement=[0.003 * math.pi / 3]))
    assert sol.success and sol.status == 0 and sol.stable is None, sol.message
    assert "frictionless twin" in sol.stability_reason and " is stable" in sol.stability_reason
