"""Work-precision: the independent references, the integrators' observed orders of
convergence, and the benchmark harness (quick setting, a subset of scenes).

No timing is asserted anywhere: the benchmark records run times, the tests check
errors, orders and the files written.
"""

import math

import closed_ref
import numpy as np
import pytest

import tendonrod as tr
from tendonrod.bench import references as refs
from tendonrod.bench import work_precision as wp
from tendonrod.bench.common import FIG11, FIG17, EI_of, read_csv, rod_of, solve_quiet
from tendonrod.bench.model_choice import run_model_choice
from tendonrod.bench.reference_robot import TendonRobotReference, from_scene

P11 = FIG11
L11, EI11 = P11["L"], EI_of(P11)
GJ11 = P11["G"] * math.pi * P11["d"] ** 4 / 32


# --------------------------------------------------------------------------- references
def test_elastica_elliptic_agrees_with_collocation_and_shooting():
    """Three independent routes to the elastica under a transverse tip force: elliptic
    integrals, collocation (solve_bvp) and the distal-balance shooting reference."""
    F = 5.0 * EI11 / L11**2
    x, z, th = refs.elastica_tip_force(L11, EI11, F)
    xb, zb, thb, _ = refs.planar_rod_bvp(L11, EI11, (F, 0.0), tol=1e-10, nodes=400)
    r = TendonRobotReference(L11, EI11, GJ11, [], F=(F, 0.0, 0.0)).solve(steps=1)
    # collocation at tol 1e-10 (residual; the solution error is far smaller, ~1e-14) and DOP853 at rtol 1e-13: both ~1e-12 of L;
    # 1e-10 leaves a factor 100 for round-off in the elliptic functions' root solve.
    assert abs(xb - x) / L11 < 1e-10 and abs(zb - z) / L11 < 1e-10
    assert np.linalg.norm(r.tip_position - [x, 0.0, z]) / L11 < 1e-10
    assert abs(thb - th) < 1e-9  # radians; same reasoning


def test_elastica_small_load_limit_is_linear_beam():
    """For F L^2/EI -> 0 the elastica's deflection tends to F L^3/(3 EI), with a
    relative correction c (F L^2/EI)^2: c must come out the same at two loads a decade
    apart (an O(F) error would change it tenfold)."""
    cs = []
    for fl in (1e-2, 1e-3):
        F = fl * EI11 / L11**2
        x, _, _ = refs.elastica_tip_force(L11, EI11, F)
        lin = F * L11**3 / (3 * EI11)
        cs.append((lin - x) / lin / fl**2)
    # c = 0.114 (measured); the next term, O(fl^4), changes it by ~1e-4 at fl = 1e-2, and
    # round-off (1e-16 / 1e-6 = 1e-10 relative at fl = 1e-3) is negligible: 1 % is ample
    assert 0.0 < cs[0] < 0.2
    assert cs[1] == pytest.approx(cs[0], rel=1e-2)


def test_compressive_elastica_and_critical_load():
    """Fig. 17's critical load: the tendon goes slack when the free elastica's tip
    angle reaches 90 deg; L sqrt(P/EI) = K(sin 45 deg) = 1.8541 (P = 3.4376 EI/L^2,
    0.358 N for the paper's robot, not the 3.6 N its text states). Checked against the
    core on the work-precision scene: taut with the tip at 90 deg just below P_c, slack
    and on the exact elastica just above."""
    p = FIG17
    L, EI, r = p["L"], EI_of(p), p["r"]
    Pc = refs.critical_tip_angle_load(L, EI, math.pi / 2)
    assert Pc * L**2 / EI == pytest.approx(1.854074677**2, rel=1e-9)  # K(1/sqrt 2), tabulated
    x, z, th = refs.elastica_compressive(L, EI, Pc)
    assert th == pytest.approx(math.pi / 2, rel=1e-12)  # consistency of the two routes
    robot = tr.Robot(rod_of(p), [tr.Tendon(offset=r)])
    opts = tr.Options(integrator="rk8", steps=64, tol=1e-12)
    below = solve_quiet(
        tr.Scene(
            robot,
            displacement=[r * math.pi / 2],
            loads=[tr.PointLoad(s=L, force=(0.0, 0.0, -0.98 * Pc))],
        ),
        opts,
    )
    assert below.success and below.tension[0] > 0.0 and below.slack[0] == 0.0
    tangent = below.tip_rotation[:, 2]
    assert np.arctan2(tangent[0], tangent[2]) == pytest.approx(
        math.pi / 2, abs=1e-9
    )  # locked tip angle
    above = solve_quiet(
        tr.Scene(
            robot,
            displacement=[r * math.pi / 2],
            loads=[tr.PointLoad(s=L, force=(0.0, 0.0, -1.02 * Pc))],
        ),
        opts,
    )
    assert above.success and above.tension[0] == 0.0 and above.slack[0] > 0.0
    x2, z2, _ = refs.elastica_compressive(L, EI, 1.02 * Pc)
    # slack: the robot is the free elastica; rk8 x 64 steps is exact to ~1e-13 of L
    assert np.hypot(above.tip_position[0] - x2, above.tip_position[2] - z2) / L < 1e-10


def test_twist_with_tendons_limits():
    """Fig. 12 exact solution: without tendon stiffness the twist is M L/GJ; with very
    stiff tendons it follows the cubic law 3 EA r^4 psi^3 / (2 L^3) = M (the tendons
    carry the moment), so psi ~ EA^(-1/3)."""
    GJ = 2.0 * EI11 / 1.3125
    M = 0.5 * GJ / L11
    psi, T = refs.twist_with_tendons(L11, GJ, 1e-12, 0.01, 3, M)
    assert psi == pytest.approx(M * L11 / GJ, rel=1e-12)  # tendons carry ~1e-20 of the moment
    EA = 1e12 * EI11 / 0.01**2
    psi, T = refs.twist_with_tendons(L11, GJ, EA, 0.01, 3, M)
    cubic = (2.0 * M * L11**3 / (3.0 * EA * 0.01**4)) ** (1.0 / 3.0)
    # the rod's own GJ psi / L is 6e-4 of M here, the helix's higher-order terms
    # (r psi / L)^2 ~ 1e-9: 1e-3 bounds both
    assert psi == pytest.approx(cubic, rel=1e-3)
    assert T == pytest.approx(EA * 0.5 * (0.01 * psi / L11) ** 2, rel=1e-3)


def test_small_load_reference_matches_analytic_ufunc():
    """The closed form the benchmarks compare against (the C ufunc tr.analytic.deflection,
    eq. 26) agrees with the independent plain-NumPy eq. 26 of tests/closed_ref.py."""
    rng = np.random.default_rng(1)
    L = 0.2
    s = rng.uniform(0, L, 50)
    z = rng.uniform(0.01, L, 50)
    b = rng.uniform(1e-3, 0.02, 50)
    a = -b / L * rng.uniform(0, 1, 50)
    k = np.where(rng.uniform(size=50) < 0.3, np.inf, rng.uniform(10, 1e5, 50))
    mine = closed_ref.deflection(s, 0.3, z, L, 4e-3, a, b, k)
    theirs = tr.analytic.deflection(s, 0.3, z, L, 4e-3, a, b, k)
    # same formula, different order of operations: agreement to a few ulps of the terms
    np.testing.assert_allclose(theirs, mine, rtol=1e-10, atol=1e-16)


# --------------------------------------------------------------------------- convergence order
def _elastica_scene():
    return [s for s in wp.wp_scenes() if s.name == "elastica"][0]


@pytest.mark.parametrize(
    "method,steps,order",
    [
        ("rk4", [4, 6, 8, 12, 16, 24, 32, 48, 64], 4),
        ("rk8", [1, 2, 3, 4, 5, 6, 8], 8),
    ],
)
def test_observed_convergence_order(method, steps, order):
    """Error against the exact elastica falls like steps^-p with p the method's order.
    The slope is a least-squares fit of log error on log steps over the asymptotic
    range (errors in (1e-13, 1e-3): above the reference's and round-off's ~1e-14,
    below the pre-asymptotic regime). Tolerance +-0.6 for RK4 and +-1.2 for RK8: the
    fit spans 1-2 decades of steps, where the next term of the error expansion can
    still move the slope by ~10-15 %; a method of the wrong order (3 or 5, 6 or 7
    for a mislabelled pair) falls outside."""
    sc = _elastica_scene()
    ref = sc.reference()
    errs = []
    for n in steps:
        sol = solve_quiet(
            sc.scene, tr.Options(integrator=method, steps=n, tol=1e-13, tip_only=True)
        )
        assert sol.success, sol.message
        assert sol.formulation.steps in (n, 0, -1) or sol.formulation.steps >= n
        errs.append(wp.tip_error(sc, sol.tip_position, ref))
    slope, used = wp.observed_order(steps, errs)
    assert used >= 3, f"too few points in the asymptotic range: errors {errs}"
    tol = 0.6 if order == 4 else 1.2
    assert abs(slope - order) < tol, f"{method}: observed order {slope:.2f} from errors {errs}"


def test_adaptive_integrator_meets_its_tolerance():
    """The adaptive integrator's tip error on the exact elastica tracks rtol (within
    a factor 100: a local-error control does not bound the global error exactly)."""
    sc = _elastica_scene()
    ref = sc.reference()
    for rt in (1e-6, 1e-9, 1e-12):
        sol = solve_quiet(
            sc.scene, tr.Options(integrator="adaptive", rtol=rt, tol=1e-13, tip_only=True)
        )
        assert sol.success, sol.message
        assert wp.tip_error(sc, sol.tip_position, ref) < 100 * rt + 1e-13


def test_fig11a_core_matches_independent_reference():
    """The core's formulation (A, B, G, H matrices) against the distal-balance form of
    reference_robot.TendonRobotReference on Fig. 11a (90 deg, transverse 1 N)."""
    sc = [s for s in wp.wp_scenes() if s.name == "fig11a"][0]
    ref = from_scene(sc.scene, rtol=1e-11).solve(steps=2).tip_position
    sol = solve_quiet(sc.scene, tr.Options(integrator="rk8", steps=32, tol=1e-13))
    assert sol.success, sol.message
    # rk8 with 32 steps: truncation ~1e-13; reference at rtol 1e-11: ~1e-11; 1e-9 is margin
    assert wp.tip_error(sc, sol.tip_position, ref) < 1e-9


@pytest.mark.parametrize("name", ["friction_exact", "friction_loaded"])
def test_friction_scene_references(name):
    """The friction scenes' references: the exact tip by Gauss-Legendre quadrature
    against SciPy's adaptive quad of the same theta(s), and the free-body shooting;
    the default solve lands on both."""
    from scipy.integrate import quad

    from tendonrod.bench.stress_friction import exact_friction_state
    from tendonrod.bench.wp_friction import EXACT

    sc = [s for s in wp.wp_scenes() if s.name == name][0]
    ref = sc.reference()
    if name == "friction_exact":
        th = exact_friction_state(*EXACT)[2]
        L = FIG17["L"]
        x = quad(lambda s: math.sin(float(th(s))), 0.0, L, epsabs=1e-14, limit=200)[0]
        z = quad(lambda s: math.cos(float(th(s))), 0.0, L, epsabs=1e-14, limit=200)[0]
        # both quadratures to ~1e-14 m; 1e-12 m is their agreement with margin
        assert np.max(np.abs(ref - [x, 0.0, z])) < 1e-12
    sol = solve_quiet(sc.scene, tr.Options())
    assert sol.success, sol.message
    # the default tolerance 1e-10 and automatic steps: 1e-9 of the tip is its accuracy
    # with margin (the work-precision summary records ~1e-14)
    assert wp.tip_error(sc, sol.tip_position, ref) < 1e-9


# --------------------------------------------------------------------------- harness
def test_work_precision_command_quick(tmp_path):
    """The quick benchmark writes the CSV (required columns, one row per scene x method
    x setting x Jacobian) and the PNG; rk8 beats rk4 on the exact circle at equal steps."""
    rows = wp.run_work_precision(
        str(tmp_path),
        quick=True,
        repeats=1,
        log=lambda *a: None,
        scenes=["circle", "elastica", "fig17_slack"],
    )
    assert (tmp_path / "work_precision.png").stat().st_size > 10000
    csvrows = read_csv(tmp_path / "work_precision.csv")
    for col in ("scene", "method", "setting", "error", "seconds", "nit", "nfev"):
        assert col in csvrows[0]
    n_set = len(wp.wp_settings(True))
    n_jac = len(wp.jacobian_methods())
    # fig17_slack also runs the paper's squared slack model; +1 default row per scene
    assert len(csvrows) == n_jac * n_set * (1 + 1 + 2) + 3
    ok = [r for r in rows if r["success"] and r["method"] != "default"]
    assert ok, "no successful solve in the quick work-precision run"
    assert all(np.isfinite(r["error"]) for r in ok)


def test_model_choice_quick(tmp_path):
    """The closed form is accurate for small loads (error O(F L^2/EI)^2 relative -> tiny)
    and wrong for large ones; the chart and CSV are written."""
    rows = run_model_choice(str(tmp_path), quick=True, log=lambda *a: None)
    assert (tmp_path / "model_choice.png").stat().st_size > 10000
    for model in {r["model"] for r in rows}:
        sub = sorted((r for r in rows if r["model"] == model), key=lambda r: r["load"])
        # up to F L^2/EI = 40 every path solve converges and stays on the loading path; at
        # 100 the warm-started solve may leave it (stress finding S7) or stall (S1): the
        # benchmark then drops the point rather than plot a wrong reference
        assert all(r["cosserat_success"] for r in sub if r["load"] <= 40.0), model
        sub = [r for r in sub if r["cosserat_success"]]
        # F L^2/EI = 1e-3: geometric nonlinearity ~1e-6 relative (plus solver error ~1e-9)
        assert sub[0]["error"] < 1e-5, (model, sub[0])
        # F L^2/EI >= 30: the small-deflection formula is off by a factor of two or more
        assert sub[-1]["load"] >= 30.0 and sub[-1]["error"] > 1.0, (model, sub[-1])
        # no tendon: the answer of record is the exact elastica (path following works)
        if model == "no tendon":
            assert max(r["cosserat_vs_exact"] for r in sub) < 1e-9
