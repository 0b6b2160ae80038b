"""The hard cases of the stress suite (findings S1, S3, S4, S5), each against an answer
obtained independently of the shooting solver: a tendon that would pass the centre of
curvature (EI/r^2 from the robot's data), tensile loads (SciPy collocation and the
linear theory of a cantilever under tension), and very stiff tendon sets (the exact
helix solution of Fig. 12, collocation of the equivalent planar rod for Fig. 18's locked
pair, and the EA^(1/3) law of the shared tension level)."""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import pytest

import tendonrod as tr
from tendonrod.bench import references as refs
from tendonrod.bench.stress_hard import _chk_opposing, _opposing_locked, _twist_scene
from tendonrod.bench.work_precision import _three_tendon_scene

# Fig. 11 robot
L, D, E, G, R = 0.1, 1.04e-3, 210e9, 80e9, 0.01
ROD = tr.Rod(L, D, E, G, kirchhoff=True)
EI = ROD.bending_stiffness
FS = EI / L**2  # force scale [N]
FIG11 = dict(L=L, d=D, E=E, G=G, r=R)


def quiet(scene, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return tr.solve(scene, **kw)


# ------------------------------------------------------------------------------ S1
@pytest.mark.parametrize(
    "F, q",
    [
        ((-30 * FS, 0, 0), R * math.pi / 2),  # stalls at 0.87 of the load, below the limit load
        ((0, 0, 100 * FS), R * math.pi / 2),
        ((-100 * FS, 0, 0), 0.0),
        ((0, 0, 15**2 * FS), R * math.pi / 4),  # tensile: the curvature gathers at the tip
    ],
)
def test_s1_names_tendon_arc_length_tension_and_limit(F, q):
    one = tr.Robot(ROD, [tr.Tendon(offset=R)])
    sol = quiet(tr.Scene(one, displacement=[q], loads=[tr.PointLoad(s=L, force=F)]))
    assert not sol.success
    msg = sol.message
    assert msg.startswith("tendon 0 would pass the centre of curvature"), msg
    s = float(re.search(r"at s = ([0-9.e+-]+) m", msg).group(1))
    tau = float(re.search(r"with tension ([0-9.e+-]+) N", msg).group(1))
    limit = float(re.search(r"limit EI/r\^2 = ([0-9.e+-]+) N", msg).group(1))
    # the limit from the robot's data (4 significant digits printed)
    assert abs(limit - EI / R**2) < 1e-3 * EI / R**2
    # a moment-free tip with one parallel tendon: kappa(L) = tau r / EI, the largest
    # curvature, so the approach is at the tip (to the walk's L/32 resolution)
    assert abs(s - L) <= L / 32
    # |w| / |w_ref| = 1 - tau r^2/EI < 0.1 at the kept stall state
    assert 0.9 * EI / R**2 <= tau <= 1.001 * EI / R**2


def test_s1_balanced_tendons_are_not_blamed():
    """Three tendons sharing 50 kN bend nothing: no centre-of-curvature message even though
    the tension is 400 EI/r^2 (the old tension-only rule named it)."""
    sol = quiet(_twist_scene(1e12), options=tr.Options(max_iter=3, continuation=False))
    assert "centre of curvature" not in sol.message


# ------------------------------------------------------------------------------ S3
@pytest.mark.parametrize("lam", [15.0, 20.0, 30.0])
def test_s3_tensile_plain_rod_by_default_vs_collocation(lam):
    T = lam**2 * FS
    sol = quiet(tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(s=L, force=(FS, 0, T))]))
    assert sol.success, sol.message
    f = sol.formulation
    assert f.shooting_auto and f.shooting_segments == math.ceil(lam / 4)
    assert abs(f.shooting_growth - lam) < 1e-3 * lam  # midpoint rule of a constant: exact
    x, z, _, _ = refs.planar_rod_bvp(L, EI, (FS, T), tol=1e-11, nodes=800)
    # collocation to 1e-11 (measured agreement 3e-16 L); 1e-9 L leaves room for tol
    assert math.hypot(sol.tip_position[0] - x, sol.tip_position[2] - z) < 1e-9 * L


@pytest.mark.parametrize("lam", [15.0, 30.0])
def test_s3_tiny_transverse_load_vs_linear_theory(lam):
    """EI w'''' - T w'' = 0, clamped, moment-free tip, shear P: w(L) = P (kL - tanh kL)/(T k)."""
    T = lam**2 * FS
    P = 1e-4 * FS
    sol = quiet(tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(s=L, force=(P, 0, T))]))
    assert sol.success, sol.message
    k = math.sqrt(T / EI)
    w = P / (T * k) * (k * L - math.tanh(k * L))
    # the nonlinear terms are ~(P/T)^2 ~ 1e-13 relative; measured 1e-13: 1e-9
    assert abs(sol.tip_position[0] - w) < 1e-9 * w


def test_s3_tendon_at_45_degrees_vs_collocation():
    """A parallel tendon at 45 deg with fixed tension tau stays parallel to the backbone (it
    bends in the tendon's plane): the planar rod with tip moment tau r, turned to 45 deg."""
    T, tau = 30.0**2 * FS, 5.0
    robot = tr.Robot(ROD, [tr.Tendon(offset=R, angle=math.pi / 4)])
    sol = quiet(tr.Scene(robot, tension=[tau], loads=[tr.PointLoad(s=L, force=(0, 0, T))]))
    assert sol.success and sol.formulation.shooting_auto, sol.message
    x, z, _, _ = refs.planar_rod_bvp(L, EI, (0.0, T), M=tau * R, tol=1e-11, nodes=800)
    c = math.cos(math.pi / 4)
    # collocation to 1e-11; the suite's 1e-6 L verification threshold
    assert np.linalg.norm(sol.tip_position - [x * c, x * c, z]) < 1e-6 * L


def test_s3_choice_leaves_ordinary_scenes_alone():
    for lam in (1.0, 10.0):
        sc = tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(s=L, force=(FS, 0, lam**2 * FS))])
        f = quiet(sc).formulation
        assert f.shooting_segments == 1 and not f.shooting_auto
    sc = tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(s=L, force=(FS, 0, 900 * FS))])
    assert quiet(sc, options=tr.Options(auto_shooting=False)).formulation.shooting_segments == 1
    # compressive and transverse loads do not grow the sensitivities exponentially
    sc = tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(s=L, force=(100 * FS, 0, -FS))])
    assert quiet(sc).formulation.shooting_segments == 1


# ------------------------------------------------------------------------- S4, S5
@pytest.mark.parametrize("alpha", [1e9, 1e10, 1e12])
def test_s5_twist_of_very_stiff_tendons_vs_exact(alpha):
    sol = quiet(_twist_scene(alpha))
    assert sol.success, sol.message
    Mz = sol.scene.point_loads[0].moment[2]
    psi, T = refs.twist_with_tendons(L, ROD.torsional_stiffness, alpha * EI / R**2, R, 3, Mz)
    Rt = sol.tip_rotation
    # exact helix solution; measured 1e-9 relative; the suite's 1e-6
    assert abs(math.atan2(Rt[1, 0], Rt[0, 0]) - psi) < 1e-6 * psi
    np.testing.assert_allclose(sol.tension, T, rtol=1e-6)


def test_s4_stiff3_shared_tension_follows_the_cube_root_law():
    """stiff3 up to 1e12: at large r^2 EA/EI the shared level tau is fixed by the tendons'
    second-order lengthening (~ tau^-2) against their stretch (~ tau / EA), so
    tau ~ EA^(1/3): a factor 100 in EA multiplies it by 100^(1/3) = 4.64."""
    taus = []
    for a in (1e10, 1e12):
        sol = quiet(_three_tendon_scene("s", "", FIG11, a, 0.5).scene)
        assert sol.success, sol.message
        assert "solved along its own direction" in sol.message
        taus.append(float(np.mean(sol.tension)))
    # the law is asymptotic (the load's own share, ~20 N of 5e3-2.5e4, shifts it): 1 %
    assert abs(taus[1] / taus[0] / 100 ** (1 / 3) - 1) < 1e-2


def test_fig18_pair_at_the_papers_stiffness_vs_collocation():
    sol = quiet(_opposing_locked(8.29e6))
    assert sol.success, sol.message
    e, ok, _ = _chk_opposing()(sol)
    assert ok, e  # see _chk_opposing for the 1e-5 bound (measured below 1e-6)


def test_stiffness_limit_of_the_opposing_pair_is_named():
    """From r^2 EA/EI ~ 1e8 the pair's shared level moves the residuals by less than their
    rounding: refused, with the resolution in N."""
    sol = quiet(_opposing_locked(1e10))
    assert not sol.success
    assert "not determined in double precision" in sol.message
    assert re.search(r"only to \+-[0-9.e+-]+ N", sol.message)


def test_s4_stiff3_vs_independent_ode():
    """The work-precision scene stiff3 (r^2 k L/EI = 1e8) by default, against the tip of an
    independent ODE solution (bench/results/references.json, 105 s of SciPy)."""
    sol = quiet(_three_tendon_scene("stiff3", "", FIG11, 1e8, 0.5).scene)
    assert sol.success, sol.message
    ref = np.array([0.06365076554595289, 0.0017217910901127303, 0.06365490149666979])
    # measured 1.9e-11 L; the reference's own accuracy is ~1e-10 L
    assert np.linalg.norm(sol.tip_position - ref) < 1e-9 * L


def test_s3_problem_compiled_for_small_loads_says_what_it_needs():
    """The segments are chosen when a scene is compiled: a Problem built at a small load
    keeps single shooting, and its failure at L sqrt(T/EI) = 30 says how many it needs."""

    def scene(lam):
        return tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(s=L, force=(FS, 0, lam**2 * FS))])

    prob = tr.Problem(scene(1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = prob.solve(scene(30.0))
    assert not sol.success
    assert "would be compiled with 8 shooting segments" in sol.message
