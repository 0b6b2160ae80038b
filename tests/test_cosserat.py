"""The Cosserat-rod/tendon solver against independently known results.

References (tests/reference.py, no tendonrod inside): the paper's closed forms
(Sections II-III) in the small-load limit, exact circles, the elastica by elliptic
integrals, a from-scratch planar SciPy shooting solver, and balance laws.

Sign convention of the closed forms: with the tendon at +x, F > 0 is the world force
-F e_x, and the deflection is positive toward F (so x = -delta).
"""

import dataclasses
import math
import warnings

import closed_ref
import numpy as np
import pytest
import reference as ref

import tendonrod as tr

pytestmark = pytest.mark.skipif(
    not hasattr(tr._core, "solve"), reason="tendonrod._core.solve not built yet"
)

# Paper Figs. 17-18 robot: L = 0.2 m, d = 0.8 mm, E = 207 GPa, G = 79.6 GPa.
L17, D17, E17, G17 = 0.2, 0.8e-3, 207e9, 79.6e9
KIRCH17 = tr.Rod(L17, D17, E17, G17, kirchhoff=True)
COSS17 = tr.Rod(L17, D17, E17, G17)
EI17 = KIRCH17.bending_stiffness
R_OFF = 0.01

# Reference solve: adaptive integrator at rtol 1e-12 and a tight residual, so that what
# remains of a comparison is the model difference, not the numerics.
REF_OPTS = tr.Options(integrator="adaptive", rtol=1e-12, tol=1e-12)


def tip_xz_theta(sol):
    p, R = sol.tip_position, sol.tip_rotation
    return p[0], p[2], math.atan2(R[0, 2], R[2, 2])


def quiet_solve(scene, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("error", tr.ConvergenceWarning)
        return tr.solve(scene, **kw)


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


# =============================================================== small loads vs closed forms
def _closed_case(kind):
    """(robot, closed-form params (a, b, k), backbone shear GA or inf) for a case."""
    rod = KIRCH17
    # sloped tendons start at 50 mm (slope up to 0.25): the F^2 part of the difference
    # scales like a^2 and must dominate the F^3 part to be seen over a factor 8 of loads;
    # this also tests the exact a/c, b/c, EA/(cL) mapping where c - 1 = 3 % is not small
    R_S = 0.05
    if kind == "parallel":
        t = tr.Tendon(offset=R_OFF)
    elif kind == "parallel-stretch":  # r^2 k L / EI = 5 with k = EA/L
        t = tr.Tendon(offset=R_OFF, EA=5 * EI17 / R_OFF**2)
    elif kind == "converging":
        t = tr.Tendon.converging(offset=R_S, length=L17)
    elif kind == "converging-stretch":  # b^2 k L/EI = 20
        t = tr.Tendon.converging(offset=R_S, length=L17, EA=20 * EI17 / R_S**2)
    elif kind == "semi-converging":  # b^2 k L/EI = 50
        t = tr.Tendon(offset=R_S, slope=-0.5 * R_S / L17, EA=50 * EI17 / R_S**2)
    else:
        raise KeyError(kind)
    a, b, k = ref.sloped_closed_params(t.slope, t.offset, t.EA, L17)
    return tr.Robot(rod, [t]), (a, b, k)


# Order of the model difference (Cosserat minus closed form) in the load. For a parallel
# tendon on a Kirchhoff backbone the planar equations are odd under (F, kappa, tau) ->
# -(F, kappa, tau): the tendon path length is exactly int (1 - r kappa) and its moment
# exactly tau r, so the difference has no F^2 term and shrinks like F^3. A sloped tendon's
# path length sqrt(a^2 + (1 - rho kappa)^2) has an even part: the difference shrinks like
# F^2. Either way at least like the load squared; we check the order predicted.
ORDER = {
    "parallel": 3,
    "parallel-stretch": 3,
    "converging": 2,
    "converging-stretch": 2,
    "semi-converging": 2,
}
# deflection/L of the smallest load: large enough that the F^3 remainder (~(delta/L)^2
# delta) stays 1e3 x above the reference integrator's 1e-12 accuracy, small enough that
# the next order changes the fitted slope by < 0.1 over the factor-8 load range
DEFL = {2: 5e-4, 3: 5e-3}
FIT_TOL = 0.15  # allowed deviation of the fitted order (next-order terms over the range)
SMALL_OPTS = dict(integrator="adaptive", rtol=1e-12, tol=1e-12)


def _fitted_order(forces, errs):
    return np.polyfit(np.log(forces), np.log(errs), 1)[0]


def _linear_part(forces, errs):
    """Fit errs = c1 F + c2 F^2 + c3 F^3; return |c1| F_max / max|errs| (0 if no F term)."""
    A = np.stack([forces, forces**2, forces**3], axis=1)
    c = np.linalg.lstsq(A / forces[:, None] ** 2, np.asarray(errs) / forces**2, rcond=None)[0]
    return abs(c[0]) * forces[-1] / np.max(np.abs(errs))


@pytest.mark.parametrize("kind", list(ORDER))
@pytest.mark.parametrize("zeta", [1.0, 0.6])
def test_small_loads_reproduce_closed_forms(kind, zeta):
    robot, (a, b, k) = _closed_case(kind)
    z = zeta * L17
    order = ORDER[kind]
    F0 = DEFL[order] * L17 * 3 * EI17 / z**3
    forces = F0 * 2.0 ** np.arange(4)
    nodes = np.array([0.5 * z, z, L17]) if z < L17 else np.array([0.5 * z, L17])
    opts = tr.Options(nodes=nodes, **SMALL_OPTS)
    err_x, err_tau, scale = [], [], []
    for F in forces:
        sc = tr.Scene(robot, displacement=[0.0], loads=[tr.PointLoad(s=z, force=(-F, 0, 0))])
        sol = quiet_solve(sc, options=opts)
        tau = closed_ref.tension(F, z, L17, EI17, a, b, k)
        delta = closed_ref.deflection_given_tau(nodes, F, z, EI17, a, b, tau)
        err_x.append(np.max(np.abs(sol.position[:, 0] + delta)))  # x = -delta
        err_tau.append(sol.tension[0] - tau)  # signed: F^2 and F^3 parts may cancel
        scale.append(F * z**3 / (3 * EI17))
        assert np.all(np.abs(sol.position[:, 1]) < 1e-15)  # planar scene: y stays 0
        assert sol.slack[0] == 0.0 and sol.tension[0] > 0
        # the library's ufuncs (another helper's C code) agree with the paper's formulas
        np.testing.assert_allclose(tr.analytic.tension(F, z, L17, EI17, a, b, k), tau, rtol=1e-12)
        np.testing.assert_allclose(
            tr.analytic.deflection(nodes, F, z, L17, EI17, a, b, k), delta, rtol=1e-11, atol=1e-18
        )
    err_x, err_tau, scale = map(np.asarray, (err_x, err_tau, scale))
    if kind == "converging" and zeta == 1.0:
        # exact, not only small-load: eqs. 25-26 give tau = F L/b and m(s) = F (s - L) +
        # (b - b s/L) tau = 0, so the robot stays straight (a truss); the straight rod with
        # tension F c L/b also solves the Cosserat equations at any load. Round-off only.
        # positions to round-off; tensions to the residual tolerance 1e-12 x EI/L^2 (x10)
        assert np.all(err_x < 1e-13 * L17) and np.all(err_tau < 1e-11 * EI17 / L17**2)
        return
    # small: the difference is a geometric nonlinearity, ~ (delta/L)^(order-1) delta
    assert np.all(err_x < 10 * scale * (scale / L17) ** (order - 1)), (err_x, scale)
    slope_x = _fitted_order(forces, err_x)
    assert abs(slope_x - order) < FIT_TOL, (slope_x, err_x)
    # tension: the signed difference has no part linear in F (the closed form is the exact
    # linearisation); its F^2 and F^3 parts can cancel near one load, so fit them instead of
    # a log slope
    assert _linear_part(forces, err_tau) < 1e-2, err_tau


def test_small_loads_extensible_backbone_eq16_17():
    """Cosserat backbone with axial stiffness k_B = EA/L in series with the tendon (eq. 17),
    plus the first-order shear deflection F min(s, z)/GA of a shearable rod."""
    EA_b = 5 * EI17 / R_OFF**2  # r^2 k_B L/EI = 5
    rod = tr.Rod(L17, D17, E17, G17, EA=EA_b)
    GA = rod.shear_stiffness
    for EA_t in (math.inf, 3 * EI17 / R_OFF**2 * L17):
        robot = tr.Robot(rod, [tr.Tendon(offset=R_OFF, EA=EA_t)])
        k = math.inf if math.isinf(EA_t) else EA_t / L17
        keq = closed_ref.equivalent_stiffness(k, EA_b / L17)
        for z in (L17, 0.7 * L17):
            F0 = DEFL[3] * L17 * 3 * EI17 / z**3
            forces = F0 * 2.0 ** np.arange(4)
            errs, err_tau = [], []
            for F in forces:
                sc = tr.Scene(
                    robot, displacement=[0.0], loads=[tr.PointLoad(s=z, force=(-F, 0, 0))]
                )
                sol = quiet_solve(sc, options=tr.Options(nodes=np.array([z, L17]), **SMALL_OPTS))
                tau = closed_ref.tension(F, z, L17, EI17, 0.0, R_OFF, keq)
                delta = closed_ref.deflection_given_tau(
                    np.array([z, L17]), F, z, EI17, 0.0, R_OFF, tau
                )
                delta = delta + F * np.minimum([z, L17], z) / GA
                errs.append(np.max(np.abs(sol.position[:, 0] + delta)))
                err_tau.append(sol.tension[0] - tau)
                np.testing.assert_allclose(
                    tr.analytic.equivalent_stiffness(k, EA_b / L17), keq, rtol=1e-14
                )
            errs = np.asarray(errs)
            slope = _fitted_order(forces, errs)
            # shear and axial strain add even terms to the odd F^3 of the Kirchhoff case:
            # at least quadratic (measured: close to 3, the even terms are tiny)
            assert slope > 2.0 - FIT_TOL, (EA_t, z, slope, errs)
            assert _linear_part(forces, err_tau) < 1e-2, err_tau  # tension exact to first order


@pytest.mark.parametrize(
    "n, routing",
    [(2, "parallel"), (3, "parallel"), (4, "parallel"), (3, "converging"), (4, "converging")],
)
def test_small_loads_pretensioned_sets(n, routing):
    """n equally spaced pretensioned tendons (phi_i = 2 pi i/n): k -> k sum cos^2 phi_i
    (eqs. 20, 36); tendon i carries tau_p + cos(phi_i) T / P."""
    EA_t = 10 * EI17 / R_OFF**2 * L17  # r^2 k L/EI = 10 per tendon
    tau_p = 1.0
    mk = (
        (lambda phi: tr.Tendon(offset=R_OFF, angle=phi, EA=EA_t, pretension=tau_p))
        if routing == "parallel"
        else (
            lambda phi: tr.Tendon.converging(
                offset=R_OFF, angle=phi, length=L17, EA=EA_t, pretension=tau_p
            )
        )
    )
    phis = 2 * np.pi * np.arange(1, n + 1) / n
    robot = tr.Robot(KIRCH17, [mk(p) for p in phis])
    P = closed_ref.pattern_factor_sum(n)
    t0 = robot.tendons[0]
    a, b, _ = ref.sloped_closed_params(t0.slope, t0.offset, EA_t, L17)
    # Hooke's law acts on the rest length, which pretension shortens to s_r/(1 + tau_p/EA):
    # the spring constant of a pretensioned tendon is EA/s_rest = (EA + tau_p)/(c L)
    k = (EA_t + tau_p) / (math.sqrt(1 + t0.slope**2) * L17)
    z = 0.8 * L17
    F0 = DEFL[3 if routing == "parallel" else 2] * L17 * 3 * EI17 / z**3
    forces = F0 * 2.0 ** np.arange(4)
    errs, err_tau = [], []
    for F in forces:
        sc = tr.Scene(robot, displacement=[0.0] * n, loads=[tr.PointLoad(s=z, force=(-F, 0, 0))])
        sol = quiet_solve(sc, options=tr.Options(nodes=np.array([z, L17]), **SMALL_OPTS))
        T = closed_ref.tension(F, z, L17, EI17, a, b, k * P)
        delta = closed_ref.deflection_given_tau(np.array([z, L17]), F, z, EI17, a, b, T)
        taus = tau_p + np.cos(phis) * T / P
        errs.append(np.max(np.abs(sol.position[:, 0] + delta)))
        err_tau.append(sol.tension - taus)
    errs, err_tau = np.asarray(errs), np.asarray(err_tau)
    # tension changes: cos(phi_i) T/P to first order (T: the largest load's resultant)
    if routing == "parallel":
        for i in range(n):
            if np.max(np.abs(err_tau[:, i])) > 1e-12:  # below: round-off at tendons with cos = 0
                assert _linear_part(forces, err_tau[:, i]) < 1e-2, (i, err_tau[:, i])
    else:
        # the geometric-stiffness change (~3e-5 relative, below) plus F^2 terms: 1e-3 of T
        assert np.max(np.abs(err_tau[-1])) < 1e-3 * abs(T), err_tau[-1]
    # pretension on sloped tendons adds a small geometric stiffness that eq. 36 leaves out
    # (docs/model.md): it is linear in F, so for converging sets only the size is checked
    scale = forces * z**3 / (3 * EI17)
    if routing == "parallel":
        slope = _fitted_order(forces, errs)
        assert abs(slope - 3.0) < FIT_TOL, (slope, errs)  # odd symmetry, as ORDER["parallel"]
        assert np.all(errs < 2.0 * scale**2 / L17)
    else:
        # the pretension's geometric stiffness on sloped tendons (left out of eq. 36): a
        # first-order relative change of order tau_p a^2 L^2/EI (2.4e-5 here; measured 3-4e-5)
        g = tau_p * a**2 * L17**2 / EI17
        assert np.all(errs < 3 * g * scale), (errs / scale, g)

        # ... and it is the pretension's: doubling tau_p doubles the discrepancy
        def tip_diff(tp):
            rob2 = tr.Robot(
                KIRCH17,
                [
                    tr.Tendon.converging(offset=R_OFF, angle=p, length=L17, EA=EA_t, pretension=tp)
                    for p in phis
                ],
            )
            k2 = (EA_t + tp) / (math.sqrt(1 + t0.slope**2) * L17)
            F = forces[0]
            sol = quiet_solve(
                tr.Scene(rob2, displacement=[0.0] * n, loads=[tr.PointLoad(s=z, force=(-F, 0, 0))]),
                options=tr.Options(nodes=np.array([L17]), **SMALL_OPTS),
            )
            T = closed_ref.tension(F, z, L17, EI17, a, b, k2 * P)
            return -sol.position[0, 0] - closed_ref.deflection_given_tau(L17, F, z, EI17, a, b, T)

        ratio = tip_diff(2 * tau_p) / tip_diff(tau_p)
        assert abs(ratio - 2.0) < 0.1, ratio  # 5 %: the F^2 remainder at the smallest load


def test_small_load_direction_isotropy_of_three_tendons():
    """Three equally spaced pretensioned tendons: the same compliance in every lateral
    direction, and the deflection is along the load (paper Section II-D)."""
    EA_t = 10 * EI17 / R_OFF**2 * L17
    robot = tr.Robot(
        KIRCH17,
        [
            tr.Tendon(offset=R_OFF, angle=2 * np.pi * i / 3, EA=EA_t, pretension=1.0)
            for i in range(3)
        ],
    )
    F = 1e-3
    out = []
    for psi in (0.0, 0.4, np.pi / 2, 2.0):
        d = np.array([math.cos(psi), math.sin(psi), 0.0])
        sc = tr.Scene(robot, displacement=[0.0] * 3, loads=[tr.PointLoad(s=L17, force=-F * d)])
        sol = quiet_solve(sc)
        p = sol.tip_position
        along = -p[:2] @ d[:2]
        perp = abs(p[0] * d[1] - p[1] * d[0])
        out.append(along)
        assert perp < 1e-4 * along  # second-order coupling only (deflection/L ~ 1e-3)
    np.testing.assert_allclose(out, out[0], rtol=2e-3)  # isotropic to first order


# =============================================================== exact large deflections
@pytest.mark.parametrize("rod", [KIRCH17, COSS17], ids=["kirchhoff", "cosserat"])
def test_pure_end_moment_gives_circle(rod):
    M = 0.02  # N m: kappa L = M L/EI ~ 0.96 rad
    sc = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L17, moment=(0, M, 0))])
    sol = quiet_solve(sc)
    kap = M / EI17
    xs = (1 - np.cos(kap * sol.s)) / kap
    zs = np.sin(kap * sol.s) / kap
    # default rk8 aims at 1e-8 relative tip accuracy; a circle is easy, allow 1e-9 L
    np.testing.assert_allclose(sol.position[:, 0], xs, atol=1e-9 * L17)
    np.testing.assert_allclose(sol.position[:, 2], zs, atol=1e-9 * L17)
    np.testing.assert_allclose(sol.position[:, 1], 0.0, atol=1e-15)
    # constant internal moment equal to the applied one, zero force
    np.testing.assert_allclose(sol.moment, np.tile([0, M, 0], (sol.s.size, 1)), atol=1e-9 * M)
    np.testing.assert_allclose(sol.force, 0.0, atol=1e-9 * M / L17)
    # at() is exact between nodes (linear interpolation would miss by ~ h^2 kappa/8 = 1e-6 m)
    s_odd = np.array([0.0123456, 0.1111111, 0.1987654])
    st = sol.at(s_odd)
    np.testing.assert_allclose(st.position[:, 0], (1 - np.cos(kap * s_odd)) / kap, atol=1e-9 * L17)
    np.testing.assert_allclose(st.position[:, 2], np.sin(kap * s_odd) / kap, atol=1e-9 * L17)
    one = sol.at(0.0777)
    assert one.position.shape == (3,) and one.rotation.shape == (3, 3)
    np.testing.assert_allclose(one.rotation[0, 2], math.sin(kap * 0.0777), atol=1e-9)


@pytest.mark.parametrize("rod", [KIRCH17, COSS17], ids=["kirchhoff", "cosserat"])
def test_tension_controlled_parallel_tendon_constant_curvature(rod):
    tau = 2.0  # N: kappa = tau r / EI ~ 4.8 1/m, tip angle ~ 55 deg
    robot = tr.Robot(rod, [tr.Tendon(offset=R_OFF)])
    sol = quiet_solve(tr.Scene(robot, tension=[tau]))
    kap = tau * R_OFF / EI17
    # Cosserat backbone: the tendon compresses it by tau/EA, the curvature per reference
    # arc length is unchanged and the frame turns by kappa s
    stretch = 1.0 if rod.kirchhoff else 1.0 - tau / rod.axial_stiffness
    xs = (1 - np.cos(kap * sol.s)) / kap * stretch
    zs = np.sin(kap * sol.s) / kap * stretch
    np.testing.assert_allclose(sol.position[:, 0], xs, atol=1e-9 * L17)
    np.testing.assert_allclose(sol.position[:, 2], zs, atol=1e-9 * L17)
    np.testing.assert_allclose(tip_xz_theta(sol)[2], kap * L17, atol=1e-9)
    assert sol.tension[0] == tau and sol.formulation.n_unknowns == 3
    # the consistent actuator displacement: q = s_r - s = r theta_L (+ backbone shortening)
    q_expected = R_OFF * kap * L17 + (0.0 if rod.kirchhoff else tau / rod.axial_stiffness * L17)
    np.testing.assert_allclose(sol.displacement[0], q_expected, rtol=1e-8)


@pytest.mark.parametrize("rod", [KIRCH17, COSS17], ids=["kirchhoff", "cosserat"])
def test_oblique_end_moment_gives_helix_with_twist(rod):
    """A dead end moment M with bending and twist components and no force: m(s) = M in the
    world frame, so for EI1 = EI2 the body curvature is u = R^T M/EI + c e3 with the
    constant c = (1/GJ - 1/EI) M_z, and R(s) = exp(s [M/EI]x) exp(s c [e3]x): the centre line
    is a helix about M (independent of GJ), the frame twists on top of it."""
    from scipy.spatial.transform import Rotation

    M = np.array([0.004, -0.006, 0.003])  # N m: |M| L/EI ~ 0.37 rad
    sol = quiet_solve(tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L17, moment=tuple(M))]))
    assert not sol.formulation.planar
    EI, GJ = rod.bending_stiffness, rod.torsional_stiffness
    w = M / EI
    om, n = np.linalg.norm(w), M / np.linalg.norm(M)
    c = (1 / GJ - 1 / EI) * M[2]
    e3 = np.array([0.0, 0.0, 1.0])
    for k in range(0, sol.s.size, 10):
        s_ = sol.s[k]
        p = (
            math.sin(s_ * om) / om * e3
            + (1 - math.cos(s_ * om)) / om * np.cross(n, e3)
            + (s_ - math.sin(s_ * om) / om) * (n @ e3) * n
        )
        R = Rotation.from_rotvec(s_ * w).as_matrix() @ Rotation.from_rotvec(s_ * c * e3).as_matrix()
        # default rk8: 1e-8 relative accuracy target; a helix is smooth, 1e-9 L
        np.testing.assert_allclose(sol.position[k], p, atol=1e-9 * L17)
        np.testing.assert_allclose(sol.rotation[k], R, atol=1e-9)
    np.testing.assert_allclose(
        sol.moment, np.tile(M, (sol.s.size, 1)), atol=1e-9 * np.linalg.norm(M)
    )


def test_small_distributed_load_cantilever():
    """Uniform load w on a plain cantilever: delta(s) = w s^2 (6L^2 - 4Ls + s^2)/(24 EI); the
    difference is odd in w (no tendon), so it shrinks like w^3."""
    w0 = DEFL[3] * L17 * 8 * EI17 / L17**4
    ws = w0 * 2.0 ** np.arange(4)
    errs = []
    for w in ws:
        sol = quiet_solve(
            tr.Scene(tr.Robot(KIRCH17, []), loads=[tr.DistributedLoad(force=(-w, 0, 0))]),
            options=tr.Options(**SMALL_OPTS),
        )
        s_ = sol.s
        delta = w * s_**2 * (6 * L17**2 - 4 * L17 * s_ + s_**2) / (24 * EI17)
        errs.append(np.max(np.abs(sol.position[:, 0] + delta)))
        assert sol.formulation.distributed_load and sol.formulation.planar
    assert abs(_fitted_order(ws, np.array(errs)) - 3.0) < FIT_TOL, errs


@pytest.mark.parametrize("P", [0.05, 0.2, 0.5])
def test_elastica_tip_force(P):
    sc = tr.Scene(tr.Robot(KIRCH17, []), loads=[tr.PointLoad(s=L17, force=(-P, 0, 0))])
    sol = quiet_solve(sc)
    x, z, th = ref.elastica_transverse_tip_force(P, L17, EI17)
    xs, zs, ths = tip_xz_theta(sol)
    # default rk8: 1e-8 relative tip accuracy is the design goal
    assert abs(xs - x) < 1e-8 * L17 and abs(zs - z) < 1e-8 * L17 and abs(ths - th) < 1e-7
    solr = quiet_solve(sc, options=REF_OPTS)
    xr, zr, thr = tip_xz_theta(solr)
    # reference integrator: rtol 1e-12
    assert abs(xr - x) < 1e-10 * L17 and abs(zr - z) < 1e-10 * L17 and abs(thr - th) < 1e-9


def _fig11_robot(routing="parallel"):
    rod = tr.Rod(0.1, 1.04e-3, 210e9, 80e9, kirchhoff=True)
    if routing == "parallel":
        t = tr.Tendon(offset=R_OFF)
    else:
        t = tr.Tendon.converging(offset=R_OFF, length=0.1)
    return tr.Robot(rod, [t])


@pytest.mark.parametrize("routing", ["parallel", "converging"])
@pytest.mark.parametrize("load", ["transverse", "axial", "mid-span+gravity"])
def test_actuated_robot_against_planar_reference(routing, load):
    """Fig. 11 a/b: a single inextensible tendon, displacement-controlled, bent to about
    90 deg, then loaded in plane; compared with the from-scratch SciPy planar shooting."""
    robot = _fig11_robot(routing)
    L, EI = robot.rod.length, robot.rod.bending_stiffness
    t = robot.tendons[0]
    # displacement for ~90 deg unloaded: parallel r*pi/2; converging: take it from a tension solve
    tau90 = EI * (math.pi / 2) / (R_OFF * L) * (1 if routing == "parallel" else 2)
    free = quiet_solve(tr.Scene(robot, tension=[tau90]))
    q = free.displacement[0]
    loads, rloads, dist = [], [], (0.0, 0.0)
    if load == "transverse":
        loads = [tr.PointLoad(s=L, force=(-0.5, 0, 0))]
        rloads = [(L, -0.5, 0.0, 0.0)]
    elif load == "axial":
        loads = [tr.PointLoad(s=L, force=(0, 0, -0.5))]
        rloads = [(L, 0.0, -0.5, 0.0)]
    else:
        loads = [
            tr.PointLoad(s=0.04, force=(0.3, 0, 0.2), moment=(0, 0.005, 0)),
            tr.DistributedLoad(force=(0, 0, -2.0)),
        ]
        rloads = [(0.04, 0.3, 0.2, 0.005)]
        dist = (0.0, -2.0)
    sol = quiet_solve(tr.Scene(robot, displacement=[q], loads=loads), guess=free)
    rr = ref.PlanarKirchhoffRobot(
        L, EI, tendons=[dict(offset=t.offset, slope=t.slope, q=q)], loads=rloads, dist=dist
    )
    # starting guess for the reference only: the load moment about the base on the solved shape
    My0 = 0.0
    for ld in loads:
        if isinstance(ld, tr.PointLoad):
            p = sol.position[int(np.argmin(np.abs(sol.s - ld.s)))]
            My0 += np.cross(p, ld.force)[1] + ld.moment[1]
        else:
            My0 += np.cross(np.trapezoid(sol.position, sol.s, axis=0), ld.force)[1]
    r = rr.solve(M0_guess=My0, tau_guess=[sol.tension[0]])
    xs, zs, ths = tip_xz_theta(sol)
    # default rk8 targets 1e-8 relative tip accuracy; the reference is at rtol 1e-13
    assert abs(xs - r["x"]) < 1e-8 * L and abs(zs - r["z"]) < 1e-8 * L
    assert abs(ths - r["theta"]) < 1e-7
    np.testing.assert_allclose(sol.tension[0], r["tension"][0], rtol=1e-7)


# =============================================================== critical slack load (Fig. 17)
def _fig17_scene(P, q=R_OFF * math.pi / 2):
    robot = tr.Robot(KIRCH17, [tr.Tendon(offset=R_OFF)])
    return tr.Scene(robot, displacement=[q], loads=[tr.PointLoad(s=L17, force=(0, 0, -P))])


def test_fig17_tension_falls_to_slack_at_the_elastica_critical_load():
    """A single inextensible tendon locked at a 90 deg tip angle, vertical tip load -P e_z.
    While taut, the tip angle stays exactly 90 deg (parallel tendon: s_1 = L - r theta_L)
    and the tension falls; at the critical load the tendon carries nothing, so the robot is a
    plain cantilever with a 90 deg tip angle under an axial dead load: the buckled elastica
    with k = sin(45 deg), P_c = K(k)^2 EI / L^2 = 0.3577 N (the paper's text says 3.6 N)."""
    Pc_exact, xc, zc = ref.elastica_compressive_tip_angle(math.pi / 2, L17, EI17)
    loads = np.linspace(0.0, 0.3, 4)
    prev, taus = None, []
    for P in loads:
        prev = quiet_solve(_fig17_scene(P), guess=prev)
        taus.append(prev.tension[0])
        # taut: tip angle held at exactly 90 deg by the length constraint
        assert abs(tip_xz_theta(prev)[2] - math.pi / 2) < 1e-9
    assert np.all(np.diff(taus) < 0) and taus[-1] > 0
    # unloaded tension of a parallel tendon: tau = EI theta/(r L) (eq. 37)
    np.testing.assert_allclose(taus[0], EI17 * (math.pi / 2) / (R_OFF * L17), rtol=1e-9)

    # find the critical load: g(P) = tension - slack * EI/(r L^2) changes sign there
    def g(P):
        s = quiet_solve(_fig17_scene(P), options=REF_OPTS)
        return s.tension[0] - s.slack[0] * EI17 / (R_OFF * L17**2)

    from scipy.optimize import brentq

    Pc = brentq(g, 0.3, 0.45, xtol=1e-12)
    # solver at rtol 1e-12, tol 1e-12: the root agrees with the exact elliptic value to 1e-8
    assert abs(Pc - Pc_exact) < 1e-8 * Pc_exact, (Pc, Pc_exact)
    sol = quiet_solve(_fig17_scene(Pc_exact), options=REF_OPTS)
    xs, zs, ths = tip_xz_theta(sol)
    assert abs(xs - xc) < 1e-9 * L17 and abs(zs - zc) < 1e-9 * L17
    assert abs(sol.tension[0]) < 1e-7 and abs(ths - math.pi / 2) < 1e-8


def test_fig17_compliance_jumps_after_slack():
    """Below P_c the tendon holds the tip angle; above it the tip is a free elastica.
    The vertical tip compliance dz/dF_z from tr.compliance matches independent values on
    both sides: finite differences of the SciPy planar reference (taut) and of the exact
    elliptic-integral elastica (slack)."""
    Pc, _, _ = ref.elastica_compressive_tip_angle(math.pi / 2, L17, EI17)
    q = R_OFF * math.pi / 2
    below, above = 0.95 * Pc, 1.05 * Pc
    C_lo = tr.compliance(_fig17_scene(below))
    C_hi = tr.compliance(_fig17_scene(above))
    sol_hi = quiet_solve(_fig17_scene(above))
    assert sol_hi.tension[0] == 0.0 and sol_hi.slack[0] > 0
    # taut reference: central difference of the planar shooting reference, h = 1e-4 N
    h = 1e-4

    def z_ref(P):
        rr = ref.PlanarKirchhoffRobot(
            L17, EI17, tendons=[dict(offset=R_OFF, q=q)], loads=[(L17, 0.0, -P, 0.0)]
        )
        return rr.solve(M0_guess=-0.2, tau_guess=[1.0])["z"]

    dz_lo = -(z_ref(below + h) - z_ref(below - h)) / (2 * h)  # dz/dF_z with F_z = -P

    # slack reference: the compressed elastica with free tip angle, parametrised by theta_L
    def elastica(th):
        P, x, z = ref.elastica_compressive_tip_angle(th, L17, EI17)
        return P, z

    th0 = 2 * math.asin(math.sqrt(0.5))
    from scipy.optimize import brentq

    thA = brentq(lambda th: elastica(th)[0] - above, th0, th0 + 0.5, xtol=1e-14)
    dth = 1e-5
    (P1, z1), (P2, z2) = elastica(thA - dth), elastica(thA + dth)
    dz_hi = -(z2 - z1) / (P2 - P1)
    # central differences: O(h^2) truncation ~ 1e-7 relative; solver 1e-8
    np.testing.assert_allclose(C_lo[2, 2], dz_lo, rtol=1e-5)
    np.testing.assert_allclose(C_hi[2, 2], dz_hi, rtol=1e-5)
    ratio = C_hi[2, 2] / C_lo[2, 2]
    assert ratio > 2.0, ratio  # the paper: "about 3 times greater"; measured value reported


def test_fig18_opposing_pretensioned_tendon_stays_taut():
    """Fig. 18: a second, opposing tendon with pretension (Cosserat backbone, so the
    pretension is defined); actuate by tension to 90 deg, lock the actuators, load 0.5 N.
    The loaded planar equilibrium is unstable out of its plane (lateral buckling: the
    pair locks the tip angle while the load compresses the proximal half at about twice
    the Euler load): the default solve says so and the in-plane comparison below is made
    with accept_unstable (test_fig18_loaded_state_buckles_out_of_plane)."""
    tau_p = 2.0
    robot = tr.Robot(
        COSS17,
        [
            tr.Tendon(offset=R_OFF, pretension=tau_p),
            tr.Tendon(offset=R_OFF, angle=np.pi, pretension=tau_p),
        ],
    )
    d_tau = EI17 * (math.pi / 2) / (R_OFF * L17)  # exact for parallel tendons (kappa = r dtau/EI)
    act = quiet_solve(tr.Scene(robot, tension=[tau_p + d_tau, tau_p]))
    assert abs(tip_xz_theta(act)[2] - math.pi / 2) < 1e-9
    q = act.displacement
    locked = quiet_solve(tr.Scene(robot, displacement=list(q)), guess=act)
    np.testing.assert_allclose(locked.tension, [tau_p + d_tau, tau_p], rtol=1e-8)
    loaded = quiet_solve(
        tr.Scene(robot, displacement=list(q), loads=[tr.PointLoad(s=L17, force=(0, 0, -0.5))]),
        guess=locked,
        options=tr.Options(accept_unstable=True),
    )
    assert np.all(loaded.tension > 0) and np.all(loaded.slack == 0)
    # both taut: s_2 - s_1 = 2 r theta_L is fixed by the locked actuators (the backbone's
    # axial strain enters both paths equally; its shear strain only at second order, ~1e-10)
    assert abs(tip_xz_theta(loaded)[2] - math.pi / 2) < 1e-8
    # independent: while both are taut the pair acts as one bilateral tendon carrying
    # tau_1 - tau_2 (which may be negative); the SciPy planar reference with a single
    # tendon at q = r pi/2 does exactly that on a Kirchhoff backbone. The Cosserat backbone
    # differs by its axial strain (tau_1 + tau_2)/EA ~ 7e-5: allow 2e-4 relative.
    r = ref.PlanarKirchhoffRobot(
        L17,
        EI17,
        tendons=[dict(offset=R_OFF, q=R_OFF * math.pi / 2)],
        loads=[(L17, 0.0, -0.5, 0.0)],
    ).solve(M0_guess=0.0, tau_guess=[1.0])
    assert r["tension"][0] < 0  # a single tendon would have to push: it goes slack
    np.testing.assert_allclose(loaded.tip_position[[0, 2]], [r["x"], r["z"]], atol=2e-4 * L17)
    np.testing.assert_allclose(loaded.tension[0] - loaded.tension[1], r["tension"][0], rtol=2e-3)
    single = quiet_solve(_fig17_scene(0.5))
    assert single.slack[0] > 0
    d_two = np.linalg.norm(loaded.tip_position - act.tip_position)
    d_one = np.linalg.norm(single.tip_position - quiet_solve(_fig17_scene(0.0)).tip_position)
    assert d_two < d_one, (d_two, d_one)  # measured: 65 mm vs 113 mm


def test_fig18_loaded_state_buckles_out_of_plane():
    """The Fig. 18 robot (opposing pretensioned pair locked at 90 deg) under 0.5 N: the
    planar equilibrium has one unstable mode.  Independent check: the tangent compliance
    (the implicit-function route on the shooting Jacobian, not the energy Hessian) has a
    negative out-of-plane entry, C_yy < 0 -- the tip moves against a lateral force.  The
    default planar solve does not report it as a success and says how to leave the plane;
    the spatial solve with a 1 mN lateral imperfection reaches a stable, laterally
    buckled state far from the plane."""
    tau_p = 2.0
    robot = tr.Robot(
        COSS17,
        [
            tr.Tendon(offset=R_OFF, pretension=tau_p),
            tr.Tendon(offset=R_OFF, angle=np.pi, pretension=tau_p),
        ],
    )
    d_tau = EI17 * (math.pi / 2) / (R_OFF * L17)
    q = quiet_solve(tr.Scene(robot, tension=[tau_p + d_tau, tau_p])).displacement
    scene = tr.Scene(robot, displacement=list(q), loads=[tr.PointLoad(s=L17, force=(0, 0, -0.5))])
    anyway = tr.Options(accept_unstable=True)
    planar = tr.solve(scene, options=anyway, strict=True)
    assert planar.stable is False and planar.stability_index == 1
    C = tr.compliance(scene, options=anyway)
    assert C[1, 1] < 0, C[1, 1]  # measured -0.78 m/N
    with pytest.warns(tr.ConvergenceWarning, match="force_spatial"):
        default = tr.solve(scene)
    assert not default.success and default.status == 5 and default.stable is False
    side = tr.Scene(robot, displacement=list(q), loads=[tr.PointLoad(s=L17, force=(0, 1e-3, -0.5))])
    out = tr.solve(side, options=tr.Options(force_spatial=True), strict=True)
    assert out.stable is True
    assert abs(out.tip_position[1]) > 0.25 * L17  # measured 109 mm: buckled out of plane


# =============================================================== balance, round trips, formulation
def _spatial_scenes():
    rod_c = tr.Rod(0.15, 1.0e-3, 200e9, 77e9)
    rod_k = tr.Rod(0.15, 1.0e-3, 200e9, 77e9, kirchhoff=True)
    ts = [
        tr.Tendon(offset=0.008, angle=0.3, EA=2e4),
        tr.Tendon.converging(offset=0.008, angle=2.4, length=0.15),
        tr.Tendon(offset=0.006, angle=4.0, slope=-0.01, end=0.1, EA=5e3),
    ]
    loads = [
        tr.PointLoad(s=0.15, force=(0.2, -0.1, -0.3), moment=(0.002, 0, 0.001)),
        tr.PointLoad(s=0.07, force=(0.0, 0.3, 0.0)),
        tr.DistributedLoad(force=(0.0, 0.0, -0.8)),
    ]
    return [
        (
            "cosserat-mixed",
            tr.Scene(
                tr.Robot(rod_c, ts),
                displacement=[2e-3, None, 1e-3],
                tension=[None, 1.5, None],
                loads=loads,
            ),
        ),
        (
            "kirchhoff-mixed",
            tr.Scene(
                tr.Robot(rod_k, ts),
                displacement=[2e-3, 1e-3, None],
                tension=[None, None, 0.7],
                loads=loads,
            ),
        ),
        # opposing inextensible pairs on a Kirchhoff backbone: q_i + q_opposite must be < 0
        # (one of each pair slack); = 0 is indeterminate, > 0 has no equilibrium (docs/model.md)
        (
            "kirchhoff-gravity-4",
            tr.Scene(
                tr.Robot(rod_k, [tr.Tendon(offset=0.008, angle=i * np.pi / 2) for i in range(4)]),
                displacement=[3e-3, 1e-3, -4e-3, -2e-3],
                loads=[tr.DistributedLoad(force=(0.0, -0.5, -1.0))],
            ),
        ),
        (
            "cosserat-tip-loads",
            tr.Scene(
                tr.Robot(
                    rod_c,
                    [
                        tr.Tendon(offset=0.008, angle=0.3, EA=2e4),
                        tr.Tendon.converging(offset=0.008, angle=2.4, length=0.15),
                    ],
                ),
                displacement=[2e-3, None],
                tension=[None, 1.5],
                loads=[loads[0], tr.DistributedLoad(force=(0.3, 0.0, -0.8))],
            ),
        ),
    ]


def _tendon_tangent_at_base(sol, i):
    """World-frame unit tendon tangent at s = 0 (R(0) = I) from the base state."""
    rod = sol.scene.robot.rod
    t = sol.scene.robot.tendons[i]
    R0 = sol.rotation[0]
    m_b = R0.T @ sol.moment[0]
    u = m_b / np.array([rod.bending_stiffness, rod.bending_stiffness, rod.torsional_stiffness])
    v = np.array([0, 0, 1.0])
    if not rod.kirchhoff:
        v = v + (R0.T @ sol.force[0]) / np.array(
            [rod.shear_stiffness, rod.shear_stiffness, rod.axial_stiffness]
        )
    d = np.array([math.cos(t.angle), math.sin(t.angle), 0.0])
    r, dr = t.offset * d, t.slope * d
    w = np.cross(u, r) + dr + v
    return R0 @ (w / np.linalg.norm(w)), R0 @ r


@pytest.mark.parametrize(
    "name, scene", _spatial_scenes(), ids=lambda x: x if isinstance(x, str) else ""
)
def test_global_balance_and_orthonormal_frames(name, scene):
    L = scene.robot.rod.length
    pls = scene.point_loads
    nodes = np.union1d(np.linspace(0, L, 801), [p.s for p in pls])
    sol = quiet_solve(
        scene, options=tr.Options(integrator="adaptive", rtol=1e-12, tol=1e-12, nodes=nodes)
    )
    # external loads on the free body [0+, L]: point loads, distributed load, tendon cuts at s = 0
    F_ext = sum((np.array(p.force) for p in pls), np.zeros(3)) + scene.distributed_force * L
    M_ext = np.zeros(3)
    for p in pls:
        k = int(np.argmin(np.abs(sol.s - p.s)))
        M_ext += np.cross(sol.position[k], p.force) + np.array(p.moment)
    from scipy.integrate import simpson

    M_ext += np.cross(simpson(sol.position, x=sol.s, axis=0), scene.distributed_force)
    F_base, M_base = sol.force[0].copy(), sol.moment[0].copy()
    for i in range(scene.robot.n_tendons):
        that, r0 = _tendon_tangent_at_base(sol, i)
        F_base += sol.tension[i] * that
        M_base += np.cross(r0, sol.tension[i] * that)
    f_scale = np.linalg.norm(F_ext) + np.sum(sol.tension)
    m_scale = f_scale * L
    # adaptive integrator at rtol 1e-12 and residual tol 1e-12; Simpson on 801 nodes ~1e-13
    np.testing.assert_allclose(F_base, F_ext, atol=1e-9 * f_scale)
    np.testing.assert_allclose(M_base, M_ext, atol=1e-9 * m_scale)
    RtR = np.einsum("nji,njk->nik", sol.rotation, sol.rotation)
    assert np.max(np.abs(RtR - np.eye(3))) < 1e-10  # drift of an rtol-1e-12 integration
    assert np.all(np.abs(np.linalg.det(sol.rotation) - 1) < 1e-10)
    # the same with the default fast options: balance to the rk8 truncation (1e-8 relative)
    fast = quiet_solve(scene)
    np.testing.assert_allclose(fast.tip_position, sol.tip_position, atol=1e-8 * L)


@pytest.mark.parametrize(
    "name, scene", _spatial_scenes(), ids=lambda x: x if isinstance(x, str) else ""
)
def test_displacement_tension_round_trip(name, scene):
    sol = quiet_solve(scene)
    tens = tr.Scene(scene.robot, tension=list(sol.tension), loads=scene.loads)
    sol_t = quiet_solve(tens)
    # same shape: both solves converge to tol 1e-10 on the same equations
    np.testing.assert_allclose(sol_t.position, sol.position, atol=1e-9 * scene.robot.rod.length)
    np.testing.assert_allclose(sol_t.rotation, sol.rotation, atol=1e-9)
    for i, q in enumerate(scene.displacement):
        if q is not None and sol.slack[i] == 0:
            np.testing.assert_allclose(
                sol_t.displacement[i], q, atol=1e-10 * scene.robot.rod.length
            )
    back = tr.Scene(scene.robot, displacement=list(sol_t.displacement), loads=scene.loads)
    sol_b = quiet_solve(back, guess=sol_t)
    np.testing.assert_allclose(sol_b.tension, sol.tension, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(sol_b.position, sol.position, atol=1e-9 * scene.robot.rod.length)


def test_planar_vs_forced_spatial_and_formulation():
    rod = KIRCH17
    robot = tr.Robot(
        rod,
        [
            tr.Tendon(offset=R_OFF),
            tr.Tendon.converging(offset=R_OFF, angle=np.pi, length=L17),
            tr.Tendon(offset=0.005, end=0.1, EA=1e4),
        ],
    )
    sc = tr.Scene(
        robot,
        displacement=[8e-3, None, 1e-3],
        tension=[None, 0.5, None],
        loads=[
            tr.PointLoad(s=0.12, force=(0.1, 0, -0.2), moment=(0, 0.003, 0)),
            tr.DistributedLoad(force=(0.3, 0, -0.5)),
        ],
    )
    pl = quiet_solve(sc)
    sp = quiet_solve(sc, options=tr.Options(force_spatial=True))
    f, g = pl.formulation, sp.formulation
    assert f.planar and not g.planar and f.kirchhoff
    assert f.n_unknowns == 3 + 2 and g.n_unknowns == 6 + 2  # tension-controlled: no unknown
    assert f.n_length_states == 2 and f.n_stretch_terms == 1 and f.distributed_load
    assert "planar" in repr(f)
    # same equations, same tolerance: agreement to 1e-10 (positions relative to L)
    np.testing.assert_allclose(pl.position, sp.position, atol=1e-10 * L17)
    np.testing.assert_allclose(pl.rotation, sp.rotation, atol=1e-10)
    np.testing.assert_allclose(pl.tension, sp.tension, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(pl.force, sp.force, atol=1e-10 * 1.0)
    np.testing.assert_allclose(pl.moment, sp.moment, atol=1e-10 * 0.2)


def test_formulation_leaves_out_what_is_not_needed():
    plain = quiet_solve(
        tr.Scene(tr.Robot(COSS17, []), loads=[tr.PointLoad(s=L17, force=(0.1, 0, 0))])
    )
    f = plain.formulation
    assert f.planar and not f.kirchhoff and f.n_unknowns == 3 and f.n_segments == 1
    assert f.n_length_states == 0 and not f.distributed_load
    three_d = quiet_solve(
        tr.Scene(
            tr.Robot(KIRCH17, [tr.Tendon(offset=0.01, angle=0.5)]),
            tension=[1.0],
            loads=[tr.PointLoad(s=0.1, force=(0, 0.1, 0))],
        )
    )
    g = three_d.formulation
    assert not g.planar and g.n_unknowns == 6 and g.n_segments == 2 and g.n_length_states == 0
    tip = quiet_solve(
        tr.Scene(tr.Robot(KIRCH17, [tr.Tendon(offset=0.01)]), displacement=[1e-3]),
        options=tr.Options(tip_only=True),
    )
    assert tip.formulation.tip_only and tip.s.shape == (1,) and tip.s[0] == L17
    full = quiet_solve(tr.Scene(tr.Robot(KIRCH17, [tr.Tendon(offset=0.01)]), displacement=[1e-3]))
    np.testing.assert_allclose(tip.tip_position, full.tip_position, atol=1e-14)
    # a tip-only solution still warm-starts: its base state comes from the core's unknowns
    for opts in (tr.Options(tip_only=True), tr.Options(tip_only=True, force_spatial=True)):
        sc = tr.Scene(
            tr.Robot(
                KIRCH17,
                [tr.Tendon(offset=0.01), tr.Tendon.converging(offset=R_OFF, angle=2.0, length=L17)],
            ),
            displacement=[5e-3, None],
            tension=[None, 1.0],
            loads=[tr.PointLoad(s=L17, force=(0.1, 0, -0.2))],
        )
        t_only = quiet_solve(sc, options=opts)
        whole = quiet_solve(sc, options=dataclasses.replace(opts, tip_only=False))
        np.testing.assert_allclose(
            t_only.base_state, whole.base_state, atol=1e-12
        )  # same solve, round-off


# =============================================================== warm starts, compliance, errors
def test_warm_start_from_solution():
    sc1 = _fig17_scene(0.1)
    sc2 = _fig17_scene(0.11)
    cold1 = quiet_solve(sc1)
    cold2 = quiet_solve(sc2)
    warm2 = quiet_solve(sc2, guess=cold1)
    np.testing.assert_allclose(warm2.position, cold2.position, atol=1e-9 * L17)
    assert warm2.nfev <= cold2.nfev
    raw = quiet_solve(sc2, guess=cold1.base_state)  # a raw vector works too
    np.testing.assert_allclose(raw.tip_position, cold2.tip_position, atol=1e-9 * L17)
    # a planar solution warm-starts a forced-spatial solve (its Jacobian is not reused)
    sp = quiet_solve(sc2, guess=cold1, options=tr.Options(force_spatial=True))
    assert not sp.formulation.planar
    np.testing.assert_allclose(sp.tip_position, cold2.tip_position, atol=1e-9 * L17)
    np.testing.assert_allclose(raw.tip_position, cold2.tip_position, atol=1e-9 * L17)


@pytest.mark.parametrize("s_at", [None, 0.07], ids=["tip", "interior"])
def test_compliance_matches_finite_differences(s_at):
    name, scene = _spatial_scenes()[1]
    L = scene.robot.rod.length
    s_ = L if s_at is None else s_at
    C = tr.compliance(scene, s=s_at)
    assert C.shape == (6, 6)
    opts = tr.Options(integrator="adaptive", rtol=1e-12, tol=1e-12, nodes=np.array([s_]))
    base = quiet_solve(scene, options=opts)
    h = [1e-4] * 3 + [1e-4 * L] * 3  # central differences: O(h^2) ~ 1e-8 relative
    fd = np.zeros((6, 6))
    for j in range(6):
        cols = []
        for sgn in (+1, -1):
            w = np.zeros(6)
            w[j] = sgn * h[j]
            extra = tr.PointLoad(s=s_, force=tuple(w[:3]), moment=tuple(w[3:]))
            sol = quiet_solve(
                tr.Scene(
                    scene.robot,
                    displacement=scene.displacement,
                    tension=scene.tension,
                    loads=tuple(scene.loads) + (extra,),
                ),
                guess=base,
                options=opts,
            )
            dR = sol.rotation[0] @ base.rotation[0].T
            dth = 0.5 * np.array([dR[2, 1] - dR[1, 2], dR[0, 2] - dR[2, 0], dR[1, 0] - dR[0, 1]])
            cols.append(np.concatenate([sol.position[0] - base.position[0], dth]))
        fd[:, j] = (cols[0] - cols[1]) / (2 * h[j])
    # FD truncation ~1e-8 relative and solver noise 1e-12/h ~ 1e-8: 1e-4 relative is safe
    np.testing.assert_allclose(C, fd, rtol=1e-4, atol=1e-6 * np.max(np.abs(fd)))
    if s_at is not None:  # closer to the base: stiffer than at the tip
        assert np.linalg.norm(C[:3, :3]) < np.linalg.norm(tr.compliance(scene)[:3, :3])


def test_nonconvergence_warns_and_strict_raises():
    sc = _fig17_scene(0.2)
    hard = tr.Options(max_iter=1, continuation=False)
    with pytest.warns(tr.ConvergenceWarning, match="did not converge"):
        sol = tr.solve(sc, options=hard)
    assert not sol.success and "NOT converged" in repr(sol)
    with pytest.raises(tr.ConvergenceError) as e:
        tr.solve(sc, options=hard, strict=True)
    assert isinstance(e.value.solution, tr.Solution) and not e.value.solution.success


def test_solution_fields_shapes_and_repr():
    sc = tr.Scene(
        tr.Robot(KIRCH17, [tr.Tendon(offset=0.01), tr.Tendon(offset=0.01, angle=np.pi / 2)]),
        displacement=[1e-3, None],
        tension=[None, 0.5],
        loads=[tr.PointLoad(s=0.11, force=(0, 0, -0.1))],
    )
    sol = quiet_solve(sc, options=tr.Options(nodes=33))
    n = sol.s.size  # 33 uniform nodes plus the load's breakpoint twice (before/after its jump)
    assert n == 35 and np.count_nonzero(sol.s == 0.11) == 2
    assert sol.position.shape == (n, 3) and sol.rotation.shape == (n, 3, 3)
    assert sol.force.shape == (n, 3) and sol.moment.shape == (n, 3)
    k = np.flatnonzero(sol.s == 0.11)
    np.testing.assert_allclose(
        sol.force[k[0]] - sol.force[k[1]], (0, 0, -0.1), atol=1e-12
    )  # n jumps by -P
    assert sol.tension.shape == (2,) and sol.slack.shape == (2,) and sol.displacement.shape == (2,)
    assert sol.s[0] == 0.0 and sol.s[-1] == L17
    np.testing.assert_array_equal(sol.position[0], 0.0)
    np.testing.assert_array_equal(sol.rotation[0], np.eye(3))
    assert sol.success and sol.status >= 0 and sol.residual_norm <= 1e-10
    assert sol.tension[1] == 0.5 and sol.displacement[0] == pytest.approx(1e-3, abs=1e-12)
    assert np.isfinite(sol.jacobian_cond) and sol.continuation_steps >= 0
    assert "converged" in repr(sol) and "tip_position" in repr(sol)


def test_rotating_the_scene_about_the_axis_rotates_the_solution():
    """Rotate every tendon angle by psi and every load by Rz(psi): the solution must be
    p' = Rz p, R' = Rz R Rz^T (the base frame I is invariant), same tensions."""
    name, scene = _spatial_scenes()[1]
    psi = 0.7
    c, s_ = math.cos(psi), math.sin(psi)
    Rz = np.array([[c, -s_, 0], [s_, c, 0], [0, 0, 1.0]])
    rob = scene.robot
    rot_t = [
        tr.Tendon(
            offset=t.offset,
            angle=t.angle + psi,
            slope=t.slope,
            EA=t.EA,
            end=t.end,
            pretension=t.pretension,
        )
        for t in rob.tendons
    ]
    loads = []
    for ld in scene.loads:
        if isinstance(ld, tr.PointLoad):
            loads.append(tr.PointLoad(s=ld.s, force=Rz @ ld.force, moment=Rz @ ld.moment))
        else:
            loads.append(tr.DistributedLoad(force=Rz @ ld.force))
    rotated = tr.Scene(
        tr.Robot(rob.rod, rot_t),
        displacement=scene.displacement,
        tension=scene.tension,
        loads=loads,
    )
    a, b = quiet_solve(scene), quiet_solve(rotated)
    L = rob.rod.length
    # the same discrete equations in rotated coordinates: agreement to round-off amplified
    # by the shooting (1e-10 L is far above round-off, far below any physical difference)
    np.testing.assert_allclose(b.position, a.position @ Rz.T, atol=1e-10 * L)
    np.testing.assert_allclose(b.rotation, Rz @ a.rotation @ Rz.T, atol=1e-10)
    np.testing.assert_allclose(b.tension, a.tension, rtol=1e-9, atol=1e-12)


def test_at_matches_a_solve_with_those_nodes():
    name, scene = _spatial_scenes()[0]
    sol = quiet_solve(scene)
    s_q = np.array([0.031, 0.07, 0.1234, 0.15])
    st = sol.at(s_q)
    direct = quiet_solve(scene, options=tr.Options(nodes=s_q))
    # both integrate from the converged base state with the same steps: 1e-10 L
    np.testing.assert_allclose(st.position, direct.position, atol=1e-10 * 0.15)
    np.testing.assert_allclose(st.rotation, direct.rotation, atol=1e-10)
    np.testing.assert_allclose(st.force, direct.force, atol=1e-9)
    np.testing.assert_allclose(st.moment, direct.moment, atol=1e-10)
    np.testing.assert_allclose(sol.at(0.15).position, sol.tip_position, atol=1e-10 * 0.15)
    with pytest.raises(ValueError, match="arc lengths in"):
        sol.at(0.2)


@pytest.mark.parametrize(
    "kw",
    [
        dict(slack_model="squared"),
        dict(jacobian_method="newton"),
        dict(jacobian_method="hybrid"),
        dict(integrator="rk4", steps=200),
        dict(integrator="adaptive"),
        dict(continuation=False),
    ],
    ids=repr,
)
@pytest.mark.parametrize("P", [0.2, 0.5], ids=["taut", "slack"])
def test_numerical_options_do_not_change_the_answer(kw, P):
    """The options change how the equations are solved, not which: every variant agrees
    with the default (rk8) solve of the Fig. 17 scene, taut and slack, to the integrators'
    accuracy (rk4 with 200 steps: h^4 ~ 1e-9 relative)."""
    base = quiet_solve(_fig17_scene(P))
    other = quiet_solve(_fig17_scene(P), options=tr.Options(**kw))
    np.testing.assert_allclose(other.tip_position, base.tip_position, atol=1e-8 * L17)
    np.testing.assert_allclose(other.tension, base.tension, atol=1e-7)
    assert (other.slack[0] > 0) == (base.slack[0] > 0) == (P > 0.3577)


# =============================================================== random scenes: balance
def _balance_errors(sol):
    """Global force and moment balance of the robot (backbone + tendons) about the base."""
    scene = sol.scene
    L = scene.robot.rod.length
    pls = scene.point_loads
    F_ext = sum((np.array(p.force) for p in pls), np.zeros(3)) + scene.distributed_force * L
    M_ext = np.zeros(3)
    for p in pls:
        k = int(np.flatnonzero(np.isclose(sol.s, p.s, rtol=0, atol=1e-15))[0])
        M_ext += np.cross(sol.position[k], p.force) + np.array(p.moment)
    from scipy.integrate import simpson

    M_ext += np.cross(simpson(sol.position, x=sol.s, axis=0), scene.distributed_force)
    F_b, M_b = sol.force[0].copy(), sol.moment[0].copy()
    for i in range(scene.robot.n_tendons):
        th, r0 = _tendon_tangent_at_base(sol, i)
        F_b += sol.tension[i] * th
        M_b += np.cross(r0, sol.tension[i] * th)
    scale = np.linalg.norm(F_ext) + np.sum(sol.tension) + 1e-3 * EI17 / L**2
    return np.max(np.abs(F_b - F_ext)) / scale, np.max(np.abs(M_b - M_ext)) / (scale * L)


def test_random_scenes_converge_and_balance():
    """Random robots (1-4 tendons: parallel, sloped, converging, anchored mid-rod, stretchable
    or not; Kirchhoff or Cosserat), random actuation (tensions, or displacements that keep
    opposing inextensible pairs feasible) and random point/distributed loads: every solve
    converges and balances forces and moments globally."""
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    @settings(
        max_examples=25,
        deadline=None,
        derandomize=True,
        suppress_health_check=[HealthCheck.too_slow],
    )
    @given(st.data())
    def check(data):
        kir = data.draw(st.booleans())
        rod = tr.Rod(0.15, 1.0e-3, 200e9, 77e9, kirchhoff=kir)
        L = 0.15
        nt = data.draw(st.integers(1, 4))
        tendons, disp, tens = [], [], []
        for _ in range(nt):
            b = data.draw(st.floats(0.002, 0.01))
            kind = data.draw(st.sampled_from(["parallel", "sloped", "converging"]))
            end = data.draw(st.sampled_from([None, 0.1, 0.12]))
            e = L if end is None else end
            a = {"parallel": 0.0, "sloped": -0.4 * b / e, "converging": -b / e}[kind]
            EA = data.draw(st.sampled_from([math.inf, 2e3, 2e4]))
            tendons.append(
                tr.Tendon(
                    offset=b, angle=data.draw(st.floats(0, 2 * math.pi)), slope=a, EA=EA, end=end
                )
            )
            if data.draw(st.booleans()):
                tens.append(data.draw(st.floats(0.0, 2.0)))  # N: up to ~kappa L = 0.5 rad
                disp.append(None)
            else:
                # released up to 2 mm or retracted up to 1 mm: at most one retracted, so no
                # pair of opposing inextensible tendons is retracted together
                q = data.draw(st.floats(-2e-3, 1e-3))
                if any(d is not None and d > 0 for d in disp):
                    q = -abs(q)
                disp.append(q)
                tens.append(None)
        loads = []
        for _ in range(data.draw(st.integers(0, 2))):
            f = data.draw(st.lists(st.floats(-0.3, 0.3), min_size=3, max_size=3))
            m = data.draw(st.lists(st.floats(-3e-3, 3e-3), min_size=3, max_size=3))
            loads.append(
                tr.PointLoad(s=data.draw(st.sampled_from([0.05, 0.09, L])), force=f, moment=m)
            )
        if data.draw(st.booleans()):
            loads.append(
                tr.DistributedLoad(
                    force=data.draw(st.lists(st.floats(-1, 1), min_size=3, max_size=3))
                )
            )
        scene = tr.Scene(tr.Robot(rod, tendons), displacement=disp, tension=tens, loads=loads)
        nodes = np.union1d(np.linspace(0, L, 401), [p.s for p in scene.point_loads])
        sol = tr.solve(
            scene,
            options=tr.Options(integrator="adaptive", rtol=1e-12, tol=1e-12, nodes=nodes),
            strict=True,
        )
        ef, em = _balance_errors(sol)
        # adaptive integration at rtol 1e-12, residual 1e-12, Simpson on 401 nodes (~1e-12)
        assert ef < 1e-9 and em < 1e-9, (ef, em, scene)
        RtR = np.einsum("nji,njk->nik", sol.rotation, sol.rotation)
        assert np.max(np.abs(RtR - np.eye(3))) < 1e-10
        assert (
            np.all(sol.tension >= 0)
            and np.all(sol.slack >= 0)
            and np.all(sol.tension * sol.slack == 0)
        )

    check()


def test_failure_near_tendon_curvature_limit_says_so():
    """Fig. 11 robot (one inextensible tendon, 90 deg) under a transverse tip force of
    100 EI/L^2 toward the tendon side: the loading path needs a tension beyond EI/r^2,
    where the tip curvature tau r/EI reaches 1/r and the tendon would pass the centre of
    curvature (stress finding S1).  The solve fails, and its message names that limit.
    A solve whose last iterate stays far below the limit says nothing of it."""
    import math as _m

    L11, d11, r11 = 0.1, 1.04e-3, 0.01
    rod = tr.Rod(length=L11, diameter=d11, E=210e9, G=80e9, kirchhoff=True)
    fs = rod.bending_stiffness / L11**2
    one = tr.Robot(rod, [tr.Tendon(offset=r11)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        bad = tr.solve(
            tr.Scene(
                one,
                displacement=[r11 * _m.pi / 2],
                loads=[tr.PointLoad(s=L11, force=(-100 * fs, 0, 0))],
            )
        )
    assert not bad.success
    assert "EI/r^2" in bad.message and "centre of curvature" in bad.message
    ok = tr.solve(
        tr.Scene(
            one, displacement=[r11 * _m.pi / 2], loads=[tr.PointLoad(s=L11, force=(-1 * fs, 0, 0))]
        )
    )
    assert ok.success and "EI/r^2" not in ok.message
