"""The raw C entry points (tendonrod._core.solve / compliance / strerror).

Tested against what is known independently of the solver: exact circles (end moment,
tension-controlled parallel tendon, including the exact Cosserat value with axial
compression), global force and moment balance, orthonormal rotations, the planar
formulation against the spatial one, displacement <-> tension round trips, the
elastica critical load of the slack scene, the implicit-function-theorem compliance
against finite differences of full solves, and the contract (formulation dict,
shapes, errors, warm starts, honest failures).

Raw rows: rod [L, EI, GJ, EA, GA, kirchhoff]; tendon [b, phi, a, EA, t, control,
value, pretension]; load [s, Fx, Fy, Fz, Mx, My, Mz].
"""

import math
import threading
import warnings

import numpy as np
import pytest
from scipy import special

from tendonrod import _core

pytestmark = pytest.mark.skipif(not hasattr(_core, "solve"), reason="_core.solve not built")

# Paper Fig. 17 robot: L = 0.2 m, d = 0.8 mm, E = 207 GPa, G = 79.6 GPa.
L, D, E, G = 0.2, 0.8e-3, 207e9, 79.6e9
AREA, I2 = math.pi * D**2 / 4, math.pi * D**4 / 64
EI, GJ, EA, GA = E * I2, G * 2 * I2, E * AREA, G * AREA
KIRCH = np.array([L, EI, GJ, EA, GA, 1.0])
COSS = np.array([L, EI, GJ, EA, GA, 0.0])
R_OFF = 0.01
NO_T = np.zeros((0, 8))
NO_L = np.zeros((0, 7))
Z3 = np.zeros(3)
INF = np.inf
# Reference integration: GSL adaptive rk8pd at rtol 1e-12 and a tight residual, so that
# comparisons below see the model, not the numerics.
REF = dict(integrator="adaptive", rtol=1e-12, tol=1e-12)


def tendon(b=R_OFF, phi=0.0, a=0.0, ea=INF, t=L, control=0, value=0.0, pre=0.0):
    return [b, phi, a, ea, t, control, value, pre]


def load(s=L, F=(0, 0, 0), M=(0, 0, 0)):
    return [s, *F, *M]


def solve(rod, tendons=(), loads=(), dist=Z3, **kw):
    t = np.array(tendons, dtype=float).reshape(-1, 8)
    lo = np.array(loads, dtype=float).reshape(-1, 7)
    return _core.solve(rod, t, lo, np.asarray(dist, float), **kw)


def tip_angle(res):
    R = res["rotation"][-1]
    return math.atan2(R[0, 2], R[2, 2])


def circle(kappa, s, v3=1.0):
    """Planar circle bending toward +x with curvature kappa (per reference length) and
    stretch v3: x = v3 (1 - cos kappa s)/kappa, z = v3 sin(kappa s)/kappa."""
    return v3 * (1 - np.cos(kappa * s)) / kappa, v3 * np.sin(kappa * s) / kappa


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


# ------------------------------------------------------------------ exact circles
@pytest.mark.parametrize("rod", [KIRCH, COSS], ids=["kirchhoff", "cosserat"])
@pytest.mark.parametrize("spatial", [False, True])
def test_pure_end_moment_gives_circle(rod, spatial):
    kappa = 1.3 * math.pi / L  # 234 deg curl
    res = solve(rod, loads=[load(M=(0, EI * kappa, 0))], nodes=21, force_spatial=spatial, **REF)
    assert res["success"], res["message"]
    x, z = circle(kappa, res["s"])
    # no force anywhere, so v = e3 even for the Cosserat rod: the exact circle. 1e-10 L:
    # the adaptive integrator's rtol 1e-12 accumulated over the curl, with margin.
    np.testing.assert_allclose(res["position"][:, 0], x, atol=1e-10 * L)
    np.testing.assert_allclose(res["position"][:, 2], z, atol=1e-10 * L)
    np.testing.assert_allclose(res["moment"][:, 1], EI * kappa, rtol=1e-10)
    assert res["formulation"]["planar"] is (not spatial)


def test_tension_controlled_parallel_tendon_kirchhoff_circle():
    tau = 0.8 * math.pi * EI / (R_OFF * L)  # 144 deg
    res = solve(KIRCH, [tendon(control=1, value=tau)], nodes=11, **REF)
    assert res["success"], res["message"]
    kappa = tau * R_OFF / EI
    x, z = circle(kappa, res["s"])
    np.testing.assert_allclose(res["position"][:, 0], x, atol=1e-10 * L)  # as above
    np.testing.assert_allclose(res["position"][:, 2], z, atol=1e-10 * L)
    # the backbone carries -tau t^ and -tau r x t^: the tendon's pull, everywhere
    R = res["rotation"]
    np.testing.assert_allclose(res["force"], -tau * R[:, :, 2], atol=1e-10 * tau)
    # exact displacement of the tension-controlled inextensible tendon: q = tau r^2 L / EI
    np.testing.assert_allclose(res["displacement"][0], kappa * R_OFF * L, rtol=1e-10)


def test_tension_controlled_parallel_tendon_cosserat_exact():
    """Derivation (docs/model.md equations): try u = kappa e2, n_b = N e3, m_b = EI kappa e2
    constant. The tendon tangent is w = (0, 0, v3 - kappa r), so A = tau/|w| e1 e1^T and
    a = A (u x w) = (tau kappa, 0, 0). Force balance n_b' + u x n_b + a = (kappa N +
    tau kappa, 0, 0) = 0 gives N = -tau; moment balance holds (v x n_b = 0, r x a = 0);
    the tip conditions give N = -tau and EI kappa = tau r. So kappa = tau r / EI exactly,
    with the centreline compressed to v3 = 1 - tau/EA: a circle of radius v3/kappa.
    The tendon's path is (v3 - kappa r) L, so q = tau L (1/EA_t + 1/EA + r^2/EI)."""
    ea_t = 2e4
    tau = 0.7 * math.pi * EI / (R_OFF * L)
    res = solve(COSS, [tendon(ea=ea_t, control=1, value=tau)], nodes=11, **REF)
    assert res["success"], res["message"]
    kappa, v3 = tau * R_OFF / EI, 1 - tau / EA
    x, z = circle(kappa, res["s"], v3)
    # 1e-10 L: reference integration (see above); v3 - 1 = -3e-5 is resolved 1e5-fold
    np.testing.assert_allclose(res["position"][:, 0], x, atol=1e-10 * L)
    np.testing.assert_allclose(res["position"][:, 2], z, atol=1e-10 * L)
    q = tau * L * (1 / ea_t + 1 / EA + R_OFF**2 / EI)
    np.testing.assert_allclose(res["displacement"][0], q, rtol=1e-9)  # integrated path
    # ... and prescribing that displacement gives back the tension (round trip)
    back = solve(COSS, [tendon(ea=ea_t, control=0, value=q)], nodes=11, **REF)
    assert back["success"], back["message"]
    np.testing.assert_allclose(back["tension"][0], tau, rtol=1e-9)  # same, inverted
    np.testing.assert_allclose(back["position"], res["position"], atol=1e-10 * L)


# ------------------------------------------------------------------ balance laws
def _tangent0(rod, res, tendons):
    """Tendon unit tangents (world) and offsets at s = 0 from the returned base state."""
    Lr, EIr, GJr, EAr, GAr, kir = rod
    R0 = res["rotation"][0]
    nb, mb = R0.T @ res["force"][0], R0.T @ res["moment"][0]
    u = mb / np.array([EIr, EIr, GJr])
    v = np.array([0, 0, 1.0]) if kir else np.array([nb[0] / GAr, nb[1] / GAr, 1 + nb[2] / EAr])
    out = []
    for b, phi, a, *_ in tendons:
        r = b * np.array([math.cos(phi), math.sin(phi), 0])
        w = v + np.cross(u, r) + a * np.array([math.cos(phi), math.sin(phi), 0])
        out.append((R0 @ (w / np.linalg.norm(w)), R0 @ r))
    return out


def _balance_scene():
    tendons = [
        tendon(phi=0.3, value=4e-3, ea=3e4),
        tendon(phi=0.3 + 2 * math.pi / 3, a=-0.02, value=-1e-3, ea=5e4),
        tendon(phi=0.3 + 4 * math.pi / 3, control=1, value=1.5, t=0.6 * L),
    ]
    loads = [
        load(s=0.5 * L, F=(0.2, -0.3, 0.1), M=(0.01, 0, -0.02)),
        load(F=(-0.1, 0.15, -0.2), M=(0, 0.005, 0.01)),
    ]
    return tendons, loads, np.array([0.1, 0.2, -0.5])


def test_global_force_and_moment_balance_spatial():
    tendons, loads, dist = _balance_scene()
    res = solve(COSS, tendons, loads, dist, nodes=401, **REF)
    assert res["success"], res["message"]
    tau = res["tension"]
    ext_F = sum(np.array(l[1:4]) for l in loads) + L * dist
    p = res["position"]
    s = res["s"]
    # distributed moment about the origin: int p(s) x dist ds (Simpson on 401 nodes,
    # error ~ h^4 ~ 1e-13 relative)
    from scipy.integrate import simpson

    s_u, k_u = np.unique(s, return_index=True)  # breakpoints appear twice
    pxd = np.cross(p[k_u], dist)
    dist_M = np.array([simpson(pxd[:, c], x=s_u) for c in range(3)])
    ext_M = dist_M.copy()
    for l in loads:
        k = np.argmin(np.abs(s - l[0]))
        ext_M += np.cross(p[k], l[1:4]) + np.array(l[4:7])
    base_F, base_M = res["force"][0].copy(), res["moment"][0].copy()
    for (t_hat, r), ta in zip(_tangent0(COSS, res, tendons), tau):
        base_F += ta * t_hat
        base_M += ta * np.cross(r, t_hat)
    # the section at s = 0+ carries every external load (the tendons are internal);
    # 1e-9 relative: the reference integrator's truncation, with margin
    scale_F = np.abs(ext_F).max() + np.abs(tau).max()
    np.testing.assert_allclose(base_F, ext_F, atol=1e-9 * scale_F)
    np.testing.assert_allclose(base_M, ext_M, atol=1e-9 * scale_F * L)
    # internal force along the rod: n(s) + sum tau t^ = loads distal of s; check the
    # slope dn/ds = -dist where no tendon pulls change (tip segment, tendon 3 ended)
    assert res["tension"][2] == 1.5 and np.all(res["tension"][:2] > 0)


def test_rotation_orthonormal_and_tip_only():
    tendons, loads, dist = _balance_scene()
    res = solve(COSS, tendons, loads, dist, nodes=51, steps=24, integrator="rk8", tol=1e-12)
    assert res["success"], res["message"]
    R = res["rotation"]
    err = np.abs(np.einsum("nji,njk->nik", R, R) - np.eye(3)).max()
    assert err < 1e-12  # RK8 preserves R^T R to its truncation error, ~1e-14 here
    tip = solve(COSS, tendons, loads, dist, steps=24, integrator="rk8", tol=1e-12, tip_only=True)
    assert tip["s"].shape == (1,) and tip["position"].shape == (1, 3)
    assert tip["formulation"]["tip_only"]
    # the same solve; recording only differs in which nodes it stores (round-off)
    np.testing.assert_allclose(tip["position"][0], res["position"][-1], atol=1e-13)
    np.testing.assert_allclose(tip["displacement"], res["displacement"], atol=1e-13)


# ------------------------------------------------------------------ planar == spatial
@pytest.mark.parametrize("rod", [KIRCH, COSS], ids=["kirchhoff", "cosserat"])
def test_planar_and_forced_spatial_agree(rod):
    tendons = [
        tendon(value=0.01, ea=2e4),
        tendon(phi=math.pi, a=-0.02, value=-0.004),
        tendon(control=1, value=0.5, t=0.7 * L, b=0.005),
    ]
    loads = [load(s=0.4 * L, F=(0.05, 0, -0.1), M=(0, 0.003, 0)), load(F=(-0.2, 0, 0.05))]
    dist = [0.0, 0.0, -0.3]
    kw = dict(nodes=31, integrator="rk8", steps=40, tol=1e-13)
    pl = solve(rod, tendons, loads, dist, **kw)
    sp = solve(rod, tendons, loads, dist, force_spatial=True, **kw)
    assert pl["success"] and sp["success"], (pl["message"], sp["message"])
    assert pl["formulation"]["planar"] and not sp["formulation"]["planar"]
    assert pl["formulation"]["n_unknowns"] == 3 + 2 and sp["formulation"]["n_unknowns"] == 6 + 2
    # same equations, same integrator and steps: agreement to the residual tolerance
    np.testing.assert_allclose(pl["position"], sp["position"], atol=1e-10 * L)
    np.testing.assert_allclose(pl["rotation"], sp["rotation"], atol=1e-10)
    np.testing.assert_allclose(pl["tension"], sp["tension"], rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(pl["force"], sp["force"], atol=1e-10 * EI / L**2 * 10)
    assert np.all(pl["position"][:, 1] == 0)


# ------------------------------------------------------------------ round trip
def test_displacement_tension_round_trip_spatial():
    tendons = [
        tendon(value=8e-3, ea=3e4),
        tendon(phi=2 * math.pi / 3, value=-2e-3, ea=3e4),
        tendon(phi=4 * math.pi / 3, value=1e-3, ea=3e4),
    ]
    loads = [load(F=(0.0, 0.3, -0.2))]
    a = solve(COSS, tendons, loads, **REF)
    assert a["success"], a["message"]
    taut = a["tension"] > 0
    assert taut.sum() >= 2
    t2 = [row[:5] + [1, ta, 0] for row, ta in zip(tendons, a["tension"])]
    # Warm from the displacement-controlled state, as a user doing the round trip would:
    # at these tensions (~190 N each, 4.5 EI/r^2) the tension-controlled
    # scene has more than one stable equilibrium (a cold solve from the straight robot has
    # reached a looped one, tip below the base, stable with margin 0.99 EI/L, as the
    # rounding of the Newton steps varied).  The guess's base moment is off by 2 % of its
    # largest component, so that the tension-controlled Newton iteration does work.
    g = np.concatenate([a["force"][0], a["moment"][0], a["tension"], a["slack"]])
    g[3:6] += 0.02 * np.max(np.abs(g[3:6]))
    b = solve(COSS, t2, loads, guess=g, **REF)
    assert b["success"], b["message"]
    assert b["nit"] >= 1
    # same state; the tension-controlled solve reports the actuator displacement back
    np.testing.assert_allclose(b["position"], a["position"], atol=1e-10 * L)
    np.testing.assert_allclose(b["displacement"][taut], a["displacement"][taut], atol=1e-11)
    assert b["formulation"]["n_unknowns"] == 6 and a["formulation"]["n_unknowns"] == 9


# ------------------------------------------------------------------ slack (Fig. 17)
def _fig17(P, **kw):
    return solve(KIRCH, [tendon(value=R_OFF * math.pi / 2)], [load(F=(0, 0, -P))], **kw)


def test_slack_scene_taut_then_slack_at_the_elastica_load():
    """Taut, the inextensible tendon keeps the tip angle at 90 deg (its path length fixes
    int kappa ds). The tension reaches 0 when the tip load alone holds a 90 deg tip angle:
    the buckled cantilever (elastica) with P L^2 / EI = (2 K(k))^2 / 4... i.e.
    P = EI (K(k) / L)^2 with k = sin(45 deg). Past it the tendon is slack."""
    k = math.sin(math.pi / 4)
    P_crit = EI * (special.ellipk(k**2) / L) ** 2  # 0.358 N (paper text: 3.6 N)
    below = _fig17(0.98 * P_crit, **REF)
    above = _fig17(1.02 * P_crit, **REF)
    assert below["success"] and above["success"], (below["message"], above["message"])
    assert below["tension"][0] > 0 and below["slack"][0] == 0
    assert abs(tip_angle(below) - math.pi / 2) < 1e-9  # the length constraint, exactly
    assert above["tension"][0] == 0 and above["slack"][0] > 0
    assert tip_angle(above) > math.pi / 2
    # tension ~ linear in P near the switch: extrapolate to 0 at P_crit within 1 %
    t1 = _fig17(0.96 * P_crit, **REF)["tension"][0]
    t2 = below["tension"][0]
    P0 = 0.98 * P_crit + t2 * (0.02 * P_crit) / (t1 - t2)
    assert abs(P0 / P_crit - 1) < 0.01


def test_slack_far_past_critical_load_converges():
    res = _fig17(1.0)
    assert res["success"], res["message"]
    assert res["tension"][0] == 0 and res["slack"][0] > 0
    assert res["formulation"]["slack_model"] == "linear"


def test_tol_below_the_round_off_floor_is_a_success_with_its_caveat():
    """A tol below what the arithmetic can verify: the scaled residual sums terms of the
    size of the tensions (in EI/L^2; the moments with r, the lengths of the size of L in
    units of r), so it cannot be told from zero below eps times them.  The solve stops
    there with TR_ROUNDOFF (7), a success whose message names the floor, at the same
    state as a solve at a reachable tol."""
    P = 0.2
    ok = _fig17(P, tol=1e-10)
    assert ok["status"] == 0 and ok["residual_norm"] <= 1e-10, ok["message"]
    fl = _fig17(P, tol=1e-16)
    assert fl["success"] and fl["status"] == _core.STATUS_ROUNDOFF, fl["message"]
    assert "round-off floor" in fl["message"]
    # the floor from the outputs: eps x (the tension and base reaction in EI/L^2, the
    # tension's moment r tau in EI/L, the tendon's length L in units of its offset r)
    tau = fl["tension"].sum()
    reaction = np.abs(fl["unknowns"][:3]).max()
    floor = np.finfo(float).eps * max(
        L / R_OFF, reaction + max(tau * L**2 / EI, tau * R_OFF * L / EI)
    )
    assert 1e-16 < fl["residual_norm"] <= floor
    # the same equilibrium: the tip within round-off of the reachable-tol solve's
    # (1e-12 L: the residuals 1e-14 and 2e-15 scaled, times the condition of the
    # shooting problem, ~1e2 here)
    np.testing.assert_allclose(fl["position"][-1], ok["position"][-1], atol=1e-12 * L)
    # the Python layer says so: a ConvergenceWarning on a success
    import tendonrod as tr

    rod = tr.Rod(length=L, diameter=D, E=E, G=G, kirchhoff=True)
    robot = tr.Robot(rod, [tr.Tendon(offset=R_OFF, angle=0.0)])
    scene = tr.Scene(
        robot, displacement=[R_OFF * math.pi / 2], loads=[tr.PointLoad(s=L, force=(0, 0, -P))]
    )
    with pytest.warns(tr.ConvergenceWarning, match="round-off floor"):
        sol = tr.solve(scene, options=tr.Options(tol=1e-16))
    assert sol.success and sol.status == _core.STATUS_ROUNDOFF


def test_squared_slack_model_same_solutions():
    # the paper's tau = gamma^2 form: same equations, so the same solutions, taut and
    # slack (the slack one warm-started: tau'(0) = 0 makes crossing the switch hard)
    for P in (0.2, 1.0):
        lin = _fig17(P, **REF)
        g = np.concatenate([lin["force"][0], lin["moment"][0], lin["tension"], lin["slack"]])
        sq = _fig17(P, slack_model="squared", guess=g, **REF)
        assert sq["success"], sq["message"]
        assert sq["formulation"]["slack_model"] == "squared"
        np.testing.assert_allclose(sq["position"], lin["position"], atol=1e-10 * L)
        np.testing.assert_allclose(sq["tension"], lin["tension"], atol=1e-9)
        np.testing.assert_allclose(sq["slack"], lin["slack"], atol=1e-11)


# ------------------------------------------------------------------ formulation
def test_formulation_leaves_out_what_the_scene_does_not_need():
    f = solve(KIRCH, [tendon(value=1e-3)])["formulation"]
    assert f["planar"] and f["kirchhoff"] and f["n_unknowns"] == 4
    assert f["n_length_states"] == 1 and f["n_stretch_terms"] == 0 and f["n_states"] == 7
    assert f["n_segments"] == 1 and not f["distributed_load"]
    # a tension-controlled tendon adds no unknown and no path-length state
    f = solve(KIRCH, [tendon(value=1e-3), tendon(phi=math.pi, control=1, value=0.5)])["formulation"]
    assert f["n_unknowns"] == 4 and f["n_length_states"] == 1 and f["n_states"] == 7
    # finite EA adds a stretch term; an out-of-plane tendon makes it spatial
    f = solve(COSS, [tendon(value=1e-3, ea=1e4), tendon(phi=1.0, value=0.0)])["formulation"]
    assert not f["planar"] and not f["kirchhoff"] and f["n_unknowns"] == 8
    assert f["n_stretch_terms"] == 1 and f["n_states"] == 18 + 2
    # tip loads need no split; an interior load and an interior anchor do
    f = solve(KIRCH, [tendon(value=1e-3, t=0.5 * L)], [load(F=(0, 0.1, 0))])["formulation"]
    assert not f["planar"] and f["n_segments"] == 2
    f = solve(KIRCH, [tendon(value=1e-3)], [load(s=0.3 * L, F=(0.1, 0, 0))], dist=[0, 0, -1])[
        "formulation"
    ]
    assert f["planar"] and f["n_segments"] == 2 and f["distributed_load"]
    f = solve(KIRCH, integrator="rk4", steps=10)["formulation"]
    assert f["integrator"] == "rk4" and f["steps"] == 10 and f["n_unknowns"] == 3


def test_nodes_include_breakpoints_on_both_sides():
    res = solve(KIRCH, [tendon(value=1e-3, t=0.5 * L)], [load(s=0.25 * L, F=(0.1, 0, 0))], nodes=5)
    s = res["s"]
    # uniform 0, .05, .1, .15, .2 merged with the breakpoints .05 and .1, each twice
    assert s.shape == (7,)
    assert np.count_nonzero(s == 0.25 * L) == 2 and np.count_nonzero(s == 0.5 * L) == 2
    k = np.flatnonzero(s == 0.25 * L)
    # the force jumps by the point load across the two nodes at the load (round-off)
    np.testing.assert_allclose(res["force"][k[0]] - res["force"][k[1]], [0.1, 0, 0], atol=1e-12)
    # output nodes do not depend on the step count
    res2 = solve(
        KIRCH, [tendon(value=1e-3, t=0.5 * L)], [load(s=0.25 * L, F=(0.1, 0, 0))], nodes=5, steps=64
    )
    np.testing.assert_array_equal(res2["s"], s)
    custom = solve(KIRCH, [tendon(value=1e-3)], nodes=np.array([0.0, 0.05, 0.2]))
    np.testing.assert_array_equal(custom["s"], [0.0, 0.05, 0.2])


# ------------------------------------------------------------------ contract
@pytest.mark.parametrize(
    "kw, name",
    [
        (dict(rod=np.ones(5)), "rod"),
        (dict(tendons=np.ones((1, 7))), "tendons"),
        (dict(loads=np.ones((2, 6))), "loads"),
        (dict(dist=np.ones(2)), "dist"),
        (dict(guess=np.ones(3)), "guess"),
        (dict(jacobian=np.ones(4)), "jacobian"),
        (dict(nodes=1), "nodes"),
        (dict(nodes=np.array([0.1, 0.05])), "nodes"),
        (dict(steps=-1), "steps"),
        (dict(steps=10**6), "steps"),  # capped: keeps max_nfev a bound on the work
        (dict(max_iter=2**40), "max_iter"),
        (dict(max_nfev=2**70), "max_nfev"),
        (dict(tol=0.0), "tol"),
        (dict(integrator="euler"), "integrator"),
        (dict(slack_model="cubic"), "slack_model"),
        (dict(jacobian_method="exact"), "jacobian_method"),
    ],
)
def test_bad_arguments_raise_value_error_naming_them(kw, name):
    args = dict(rod=KIRCH, tendons=np.array([tendon(value=1e-3)]), loads=NO_L, dist=Z3)
    args.update(kw)
    pos = [args.pop(k) for k in ("rod", "tendons", "loads", "dist")]
    with pytest.raises(ValueError, match=name):
        _core.solve(*pos, **args)


@pytest.mark.parametrize(
    "rod, tendons, name",
    [
        (np.array([L, -EI, GJ, EA, GA, 1.0]), NO_T, "EI"),
        (np.array([L, EI, GJ, np.nan, GA, 0.0]), NO_T, "rod"),
        (KIRCH, np.array([tendon(t=2 * L)]), "end"),
        (KIRCH, np.array([tendon(ea=-1.0)]), "EA"),
        (KIRCH, np.array([tendon(control=2)]), "control"),
        (KIRCH, np.array([tendon(control=1, value=-1.0)]), "tension"),
    ],
)
def test_bad_model_values_raise_value_error(rod, tendons, name):
    with pytest.raises(ValueError, match=name):
        _core.solve(rod, tendons, NO_L, Z3)


def test_strerror_names_codes():
    assert _core.strerror(0) == "success"
    assert "indeterminate" in _core.strerror(-8)
    assert _core.strerror(12345) == "unknown status"


def test_warm_start_with_guess_and_jacobian_is_fast():
    tendons = [tendon(value=R_OFF * math.pi / 2)]
    a = solve(KIRCH, tendons, [load(F=(0.05, 0, -0.1))], steps=8, tol=1e-10, force_spatial=True)
    assert a["success"]
    g = np.concatenate([a["force"][0], a["moment"][0], a["tension"], a["slack"]])
    b = solve(
        KIRCH,
        tendons,
        [load(F=(0.0502, 0, -0.1))],
        steps=8,
        tol=1e-10,
        force_spatial=True,
        guess=g,
        jacobian=a["jacobian"],
    )
    assert b["success"] and b["nit"] <= 2, (b["nit"], b["message"])
    assert b["njev"] == 0  # the supplied Jacobian was reused: no finite differences
    # a jacobian of the wrong shape is ignored, not an error
    c = solve(KIRCH, tendons, [load(F=(0.052, 0, -0.1))], steps=8, guess=g, jacobian=np.eye(2))
    assert c["success"]


def test_non_converging_case_reports_failure_without_exception():
    res = _fig17(1.0, max_iter=1, continuation=False)
    assert res["success"] is False and res["status"] < 0
    assert "iteration" in res["message"] or "progress" in res["message"]
    assert res["nit"] <= 1
    res = _fig17(1.0, max_nfev=5)
    assert res["success"] is False and "max_nfev" in res["message"]


def test_opposing_inextensible_tendons_on_kirchhoff_fail_honestly():
    pair = [tendon(value=0.0), tendon(phi=math.pi, value=0.0)]
    res = solve(KIRCH, pair)
    assert not res["success"] and "statically indeterminate" in res["message"]
    assert _core.strerror(res["status"]) == "statically indeterminate"
    res = solve(KIRCH, [tendon(value=2e-3), tendon(phi=math.pi, value=2e-3)])
    assert not res["success"] and "no equilibrium" in res["message"]
    # three equally spaced tendons, all locked at zero: the same indeterminacy
    tri = [tendon(phi=2 * math.pi * i / 3) for i in range(3)]
    assert "statically indeterminate" in solve(KIRCH, tri)["message"]
    # one released: determinate (it goes slack, the other holds)
    res = solve(KIRCH, [tendon(value=2e-3), tendon(phi=math.pi, value=-3e-3)])
    assert res["success"], res["message"]
    assert res["tension"][0] > 0 and res["tension"][1] == 0 and res["slack"][1] > 0
    # with finite tendon EA the pair is determinate
    res = solve(KIRCH, [tendon(value=1e-3, ea=2e4), tendon(phi=math.pi, value=1e-3, ea=2e4)])
    assert res["success"], res["message"]


def test_pretension():
    # unbalanced: refused with a message
    res = solve(COSS, [tendon(pre=2.0)])
    assert not res["success"] and "not balanced" in res["message"]
    # balanced but no axial compliance anywhere: refused
    res = solve(KIRCH, [tendon(pre=2.0), tendon(phi=math.pi, pre=2.0)])
    assert not res["success"] and "compliance" in res["message"]
    # balanced on a Cosserat backbone: at q = 0 each tendon holds its pretension
    pair = [tendon(pre=2.0), tendon(phi=math.pi, pre=2.0)]
    res = solve(COSS, pair, **REF)
    assert res["success"], res["message"]
    np.testing.assert_allclose(res["tension"], [2.0, 2.0], rtol=1e-9)  # reference solve
    np.testing.assert_allclose(res["position"][:, 0], 0, atol=1e-14)
    # the backbone is uniformly compressed by the sum of the pretensions
    np.testing.assert_allclose(res["position"][-1, 2], L * (1 - 4.0 / EA), rtol=1e-12)
    # a pretensioned opposing pair keeps both taut under a load that slackens one alone
    fin = [
        tendon(value=R_OFF * 0.5, ea=1e4, pre=5.0),
        tendon(phi=math.pi, value=-R_OFF * 0.5, ea=1e4, pre=5.0),
    ]
    res = solve(COSS, fin, [load(F=(0, 0, -0.2))])
    assert res["success"] and np.all(res["tension"] > 0), res["message"]


# ------------------------------------------------------------------ compliance
def test_compliance_matches_finite_differences_of_full_solves():
    tendons = [tendon(value=R_OFF * math.pi / 3, ea=3e4), tendon(phi=2.0, value=-R_OFF, ea=3e4)]
    base_loads = [load(F=(0.0, 0.0, -0.1))]
    kw = dict(integrator="rk8", steps=40, tol=1e-12)
    base = solve(COSS, tendons, base_loads, force_spatial=True, **kw)
    assert base["success"]
    g = np.concatenate([base["force"][0], base["moment"][0], base["tension"], base["slack"]])
    s = 0.6 * L
    C = _core.compliance(COSS, np.array(tendons), np.array(base_loads), Z3, s, guess=g, **kw)
    assert C.shape == (6, 6)

    def pose(extra):
        r = solve(
            COSS, tendons, base_loads + [extra], force_spatial=True, nodes=np.array([s, L]), **kw
        )
        assert r["success"], r["message"]
        return r["position"][0], r["rotation"][0]

    for j in range(6):
        h = 1e-4 if j < 3 else 1e-5
        e = np.zeros(6)
        e[j] = h
        pp, Rp = pose(load(s=s, F=e[:3], M=e[3:]))
        pm, Rm = pose(load(s=s, F=-e[:3], M=-e[3:]))
        dx = (pp - pm) / (2 * h)
        W = (Rp - Rm) / (2 * h) @ Rp.T
        dth = 0.5 * np.array([W[2, 1] - W[1, 2], W[0, 2] - W[2, 0], W[1, 0] - W[0, 1]])
        col = np.concatenate([dx, dth])
        # central differences of full solves: O(h^2) ~ 1e-7 relative, with margin
        np.testing.assert_allclose(C[:, j], col, rtol=1e-4, atol=1e-5 * np.abs(col).max())
    # dead forces and frictionless tendons are conservative: the force block is symmetric
    Cf = C[:3, :3]
    np.testing.assert_allclose(Cf, Cf.T, atol=1e-6 * np.abs(Cf).max())


# ------------------------------------------------------------------ threads
def test_gil_released_and_deterministic_across_threads():
    tendons, loads, dist = _balance_scene()
    ref = solve(COSS, tendons, loads, dist, steps=16)
    out = [None] * 4

    def work(i):
        out[i] = solve(COSS, tendons, loads, dist, steps=16)

    th = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in th:
        t.start()
    for t in th:
        t.join()
    for o in out:
        np.testing.assert_array_equal(o["position"], ref["position"])  # bitwise


# ------------------------------------------------------------------ multiple shooting
def test_multiple_shooting_tensile_load():
    """Tension T with a small lateral tip force F: the linear theory of a tie-beam
    cantilever gives the tip deflection F L / T (1 - tanh(lam)/lam), lam = L sqrt(T/EI).
    Single shooting amplifies errors like e^lam; with M segments, like e^(lam/M)."""
    lam = 20.0
    T = lam**2 * EI / L**2
    F = 1e-4 * T
    # a hard case: its load path stalls, a direct solve converges (status 3), and the
    # confirming 8-segment solve needs ~3e7 right-hand-side evaluations, beyond the
    # default work budget; the answer itself is verified against the tie-beam theory
    res = solve(KIRCH, loads=[load(F=(F, 0, T))], shooting_segments=4, max_work=1e8)
    assert res["status"] >= 0, res["message"]
    f = res["formulation"]
    assert f["shooting_segments"] == 4 and f["n_unknowns"] == 3 + 3 * 6 and f["planar"]
    delta = F * L / T * (1 - math.tanh(lam) / lam)
    # deflection 1e-4 L: the geometric nonlinearity is ~(delta/L)^2 ~ 1e-8 relative; the
    # tie stretches nothing (Kirchhoff); 1e-6 leaves room for the integrator
    assert abs(res["position"][-1, 0] / delta - 1) < 1e-6
    # the same solution as single shooting where that still works (lam = 5)
    T5 = 25 * EI / L**2
    kw = dict(steps=40, tol=1e-12)
    one = solve(KIRCH, [tendon(value=0.003)], [load(F=(0.01 * T5, 0, T5))], **kw)
    four = solve(
        KIRCH, [tendon(value=0.003)], [load(F=(0.01 * T5, 0, T5))], shooting_segments=4, **kw
    )
    assert one["success"] and four["success"], (one["message"], four["message"])
    np.testing.assert_allclose(four["position"], one["position"], atol=1e-11 * L)  # same equations
    np.testing.assert_allclose(four["tension"], one["tension"], rtol=1e-9)
    with pytest.raises(ValueError, match="shooting_segments"):
        solve(KIRCH, shooting_segments=0)


# ------------------------------------------------------------------ large loads
@pytest.mark.parametrize("fl", [4.0, 10.0, 25.0, 100.0])
def test_large_transverse_load_follows_the_loading_branch(fl):
    """A plain cantilever under a transverse tip force F L^2/EI = fl has many equilibria
    (looped ones too); the one reached by loading is the elastica of the references
    module (elliptic integrals, no tendonrod inside). Cold starts above a scaled load
    of 6 try direct Newton first only up to 12 (an answer that stands only if stable),
    and go by continuation from the unloaded robot above: both must land on it."""
    from tendonrod.bench.references import elastica_tip_force

    F = fl * EI / L**2
    res = solve(KIRCH, loads=[load(F=(F, 0, 0))])
    assert res["success"], res["message"]
    xL, zL, _ = elastica_tip_force(L, EI, F)
    # auto steps verified to tol = 1e-10 (scaled), tip within 1e-8 L with margin
    assert (
        abs(res["position"][-1, 0] - xL) < 1e-8 * L and abs(res["position"][-1, 2] - zL) < 1e-8 * L
    )
    # direct up to the try's scale (TR_DIRECT_TRY_SCALE = 12), by continuation above
    assert (res["continuation_steps"] > 0) == (fl > 12)


@pytest.mark.parametrize("method", ["fd", "newton", "hybrid"])
def test_jacobian_methods_agree(method):
    """The three iterations solve the same equations: same answer to the tolerance."""
    tendons, loads, dist = _balance_scene()
    ref = solve(COSS, tendons, loads, dist, steps=16, tol=1e-12)
    res = solve(COSS, tendons, loads, dist, steps=16, tol=1e-12, jacobian_method=method)
    assert res["success"], res["message"]
    assert res["formulation"]["jacobian_method"] == method
    # residual 1e-12 scaled; condition ~1e3-1e4: positions agree to ~1e-9 L or better
    np.testing.assert_allclose(res["position"], ref["position"], atol=1e-9 * L)
    np.testing.assert_allclose(res["tension"], ref["tension"], rtol=1e-8, atol=1e-10)


# ------------------------------------------------------- automatic step selection
def _smallest_fixed_rk8(scene, ref_tip, rel):
    for n in range(1, 65):
        r = solve(*scene, integrator="rk8", steps=n, tip_only=True)
        if r["success"] and np.abs(r["position"][-1] - ref_tip).max() <= rel * L:
            return n
    return None


@pytest.mark.parametrize("integrator", ["rk8", "rk4"])
@pytest.mark.parametrize("P", [0.2, 0.5], ids=["taut", "slack"])
def test_automatic_steps_verified_and_not_over_resolved(integrator, P):
    """steps = 0: the step-doubling estimate of the truncation error at the chosen count
    is <= tol, the tip agrees with an adaptive rtol 1e-13 reference, and (rk8) the
    count is close to the smallest fixed count reaching 1e-10 L (finding C4: the old
    rule kept 2x the verified count, 16-40 steps where 6-10 suffice). rk4 once ran to
    the 8192-step cap with a clobbered saved tip (status TR_TRUNCATION)."""
    scene = (KIRCH, [tendon(value=R_OFF * math.pi / 2)], [load(F=(0, 0, -P))])
    ref = solve(*scene, integrator="adaptive", rtol=1e-13, tol=1e-13)["position"][-1]
    res = solve(*scene, integrator=integrator)
    assert res["status"] == 0, res["message"]
    tol = 1e-10  # the default scaled tolerance
    assert res["truncation_estimate"] <= tol
    # scaled tip state error <= tol (truncation) + tol (residual), scale ~L: 1e-9 L leaves
    # a factor 5 for the conversion between scaled residual and tip position
    assert np.abs(res["position"][-1] - ref).max() <= 1e-9 * L
    n = res["formulation"]["steps"]
    if integrator == "rk8":
        n_min = _smallest_fixed_rk8(scene, ref, 1e-10)
        # Richardson refinement aims at 0.5 tol from a doubling estimate: at most ~2x
        assert n_min is not None and n <= 2 * n_min, (n, n_min)
    else:
        assert n < 2048, n  # far from the 8192 cap


def test_stiff_tendons_under_twist_converge_cold_and_agree_with_a_warm_path():
    """Fig. 11c robot (three tendons, r^2 k L/(3 EI) = 5e4, one at the 90 deg actuation,
    two locked at zero tension) under an out-of-plane tip load: the cold solve (direct
    Newton stagnates, continuation finishes) gives the same equilibrium as a warm path
    of small load steps from the unloaded robot, each a plain Newton solve (continuation
    off), i.e. an independent route."""
    Lr, d, Er, Gr, r = 0.1, 1.04e-3, 210e9, 80e9, 0.01
    A, I = math.pi * d**2 / 4, math.pi * d**4 / 64
    rod = np.array([Lr, Er * I, Gr * 2 * I, Er * A, Gr * A, 1.0])
    EIr = Er * I
    EAt = 5e4 * 3 * EIr / r**2
    tau90 = EIr * (math.pi / 2) / (r * Lr)
    tt = [[r, 2 * math.pi * i / 3, 0, EAt, Lr, 1, tau90 if i == 0 else 0.0, 0] for i in range(3)]
    free = solve(rod, tt)
    td = [[r, 2 * math.pi * i / 3, 0, EAt, Lr, 0, free["displacement"][i], 0] for i in range(3)]
    cold = solve(rod, td, [[Lr, 0, 0.5, 0, 0, 0, 0]])
    assert cold["success"], cold["message"]
    prev = solve(rod, td)
    for f in np.geomspace(0.002, 0.5, 25):  # the tension grows fastest at small loads
        g = np.concatenate([prev["force"][0], prev["moment"][0], prev["tension"], prev["slack"]])
        prev = solve(
            rod,
            td,
            [[Lr, 0, f, 0, 0, 0, 0]],
            guess=g,
            jacobian=prev["jacobian"],
            continuation=False,
        )
        assert prev["success"], (f, prev["message"])
    # both at residual <= 1e-10 with a condition ~1e5-1e6 (common-mode tension): tensions
    # (100+ N) agree to ~1e-5 relative, the tip to 1e-8 L
    np.testing.assert_allclose(cold["tension"], prev["tension"], rtol=1e-5)
    np.testing.assert_allclose(cold["position"][-1], prev["position"][-1], atol=1e-8 * Lr)


# --------------------------------------------------------------- honesty off the load path
@pytest.mark.parametrize("lam", [15.0, 20.0])
def test_off_path_equilibrium_is_never_reported_as_success(lam):
    """Plain Kirchhoff rod under a tensile tip load T (L sqrt(T/EI) = lam) plus a
    transverse EI/L^2: single shooting amplifies errors by ~exp(2 lam), load
    continuation stalls, and a direct solve may land on a looped equilibrium (at
    lam = 20 the tip ends 0.2 L short).  Whatever the solver returns, a success must be
    the stretched rod that independent collocation (scipy solve_bvp, stable under
    tension) finds; an equilibrium found off the load path (status 3) is data with
    success = False, never a success."""
    import tendonrod as tr
    from tendonrod.bench.references import planar_rod_bvp

    L, d, E, G = 0.1, 1.04e-3, 210e9, 80e9
    rod = tr.Rod(length=L, diameter=d, E=E, G=G, kirchhoff=True)
    EI = rod.bending_stiffness
    fs = EI / L**2
    F = (fs, lam**2 * fs)
    xL, zL, _, _ = planar_rod_bvp(L, EI, F)
    for M in (1, 8):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", tr.ConvergenceWarning)
            sol = tr.solve(
                tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L, force=(F[0], 0, F[1]))]),
                options=tr.Options(shooting_segments=M),
            )
        if sol.status == tr._core.STATUS_OFFPATH:
            # success only when a second formulation confirmed the equilibrium
            assert ("; confirmed:" in sol.message) == sol.success, sol.message
        if sol.success:
            # collocation at tol 1e-10 on 400+ nodes: 1e-6 L covers both discretisations
            assert (
                abs(sol.tip_position[0] - xL) < 1e-6 * L
                and abs(sol.tip_position[2] - zL) < 1e-6 * L
            )
