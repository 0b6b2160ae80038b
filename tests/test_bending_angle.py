"""Solution.bending_angle: the angle between the base and tip tangents, for every
formulation.  Checked against the closed form of a rod under a pure tip moment: the
moment is the same in every section, so the curvature is M/EI along the moment's axis
(an axis normal to the rod: no twist) and the tangent turns by M L / EI about that axis."""

import math

import numpy as np
import pytest

import tendonrod as tr

L = 0.2
ROD = tr.Rod(length=L, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
EI = ROD.bending_stiffness

# solver tol 1e-10 (scaled) and the automatic RK8 steps' truncation (~1e-10 L): the
# closed-form angle is met to 1e-8 rad with a wide margin
TOL = 1e-8


def _moment_scene(theta, axis=(0.0, 1.0, 0.0), robot=None):
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    M = tuple(EI * theta / L * a)
    return tr.Scene(robot or tr.Robot(ROD, []), loads=[tr.PointLoad(s=L, moment=M)])


@pytest.mark.parametrize("theta", [0.0, 0.3, -1.1, 2.5])
def test_planar_bend_under_a_tip_moment(theta):
    sol = tr.solve(_moment_scene(theta))
    assert sol.success, sol.message
    assert sol.tip_angle == pytest.approx(theta, abs=TOL)
    assert sol.bending_angle == pytest.approx(abs(theta), abs=TOL)


def test_a_curl_past_pi_reads_the_angle_between_the_tangents():
    """tip_angle 4 rad (unwrapped); the tangents make 2 pi - 4 rad."""
    sol = tr.solve(_moment_scene(4.0))
    assert sol.success, sol.message
    assert sol.tip_angle == pytest.approx(4.0, abs=TOL)
    assert sol.bending_angle == pytest.approx(2 * math.pi - 4.0, abs=TOL)


@pytest.mark.parametrize("axis", [(1.0, 1.0, 0.0), (0.3, -1.0, 0.0), (1.0, 0.0, 0.0)])
def test_spatial_bend_under_a_tip_moment(axis):
    """A moment about an axis out of the x-z plane: a spatial solve (tip_angle NaN)."""
    sol = tr.solve(_moment_scene(1.2, axis), options=tr.Options(force_spatial=True))
    assert sol.success, sol.message
    assert math.isnan(sol.tip_angle)
    assert sol.bending_angle == pytest.approx(1.2, abs=TOL)


def test_mounted_robot_has_the_same_bending_angle():
    """The angle between two tangents does not depend on the frame: a robot mounted
    upside down and turned about x bends by the same angle as the unmounted one."""
    c, s = math.cos(0.7), math.sin(0.7)
    R = [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
    mounted = tr.Robot(ROD, [], base_position=(0.1, 0.2, 0.3), base_rotation=R)
    # the moment in the world frame: the base frame's y axis (R's second column)
    axis = tuple(np.array(R)[:, 1])
    sol = tr.solve(_moment_scene(0.9, axis, mounted))
    assert sol.success, sol.message
    assert sol.bending_angle == pytest.approx(0.9, abs=TOL)


def test_tendon_bend_matches_the_constant_curvature_closed_form():
    """One parallel tendon at offset r pulled with tension tau on an inextensible
    Kirchhoff rod: curvature tau r / EI, bending angle tau r L / EI."""
    r = 0.01
    tau = 0.8 * EI / (r * L)  # 0.8 rad
    sol = tr.solve(tr.Scene(tr.Robot(ROD, [tr.Tendon(offset=r)]), tension=[tau]))
    assert sol.success, sol.message
    assert sol.bending_angle == pytest.approx(0.8, abs=TOL)
