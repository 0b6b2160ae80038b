"""tr.modes: natural frequencies and mode shapes about an equilibrium, against what is
known independently -- the Euler-Bernoulli cantilever's beta L, the Rayleigh and
Timoshenko beams' frequency equations (shot with SciPy here), the torsional rod, the tip
mass's frequency equation, the tension-stiffened beam's exact determinant, a
Rayleigh-Ritz bound built from the paper's closed forms, the interlacing of the
displacement-held and tension-held robots, and the buckling point tr.path finds."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import tendonrod as tr
from tendonrod import analytic

L, D, E, G, RHO = 0.2, 2e-3, 207e9, 79.6e9, 7800.0
A = math.pi * D**2 / 4
I = math.pi * D**4 / 64
EB = {"rotary_inertia": False}  # an Euler-Bernoulli beam's mass: no rotary inertia


def _cantilever(kirchhoff=True, d=D, loads=(), length=L):
    rod = tr.Rod(length, d, E, G, density=RHO, kirchhoff=kirchhoff)
    return tr.Scene(tr.Robot(rod, []), loads=loads)


def _beta(m, length=L, d=D):
    a, i = math.pi * d**2 / 4, math.pi * d**4 / 64
    return (np.asarray(m.omega2) * RHO * a * length**4 / (E * i)) ** 0.25


def _bending(m):
    """Indices of the bending modes (lateral displacement dominant)."""
    out = []
    for k in range(m.n):
        lat = np.abs(m.shape_position[k][:, :2]).max()
        ax = np.abs(m.shape_position[k][:, 2]).max()
        twist = L * np.abs(m.shape_rotation[k][:, 2]).max()
        if lat > 10 * max(ax, twist):
            out.append(k)
    return out


def _beam_root(omega_guess, *, EI, rhoA, rhoI=0.0, GA=math.inf, tip_mass=0.0, length=L):
    """The exact frequency of a Timoshenko / Rayleigh cantilever near omega_guess: the
    linear ODE for y = (w, psi, M, Q) shot from the clamp with SciPy (rtol 1e-12), the
    tip conditions M = 0, Q = m_tip omega^2 w as a 2 x 2 determinant, its root by brentq."""

    def det(om):
        def f(s, y):
            w, psi, M, Q = y
            return [
                psi + (Q / GA if math.isfinite(GA) else 0.0),
                M / EI,
                -Q - rhoI * om**2 * psi,
                -rhoA * om**2 * w,
            ]

        cols = []
        for y0 in ([0, 0, 1.0, 0], [0, 0, 0, 1.0]):
            y = solve_ivp(f, (0, length), y0, method="DOP853", rtol=1e-12, atol=1e-20).y[:, -1]
            cols.append([y[2], y[3] - tip_mass * om**2 * y[0]])
        return cols[0][0] * cols[1][1] - cols[1][0] * cols[0][1]

    return brentq(det, 0.995 * omega_guess, 1.005 * omega_guess, xtol=1e-14 * omega_guess)


# ---------------------------------------------------------------- Euler-Bernoulli
def test_euler_bernoulli_cantilever_beta_L_both_planes():
    m = tr.modes(_cantilever(), n=6, options=EB)
    assert m.success and m.n == 6
    # the exact roots of 1 + cos b cosh b = 0 (brentq), and the 7 digits
    exact = [
        brentq(lambda b: 1 + math.cos(b) * math.cosh(b), lo, lo + 1.5, xtol=1e-15)
        for lo in (1.0, 4.0, 7.0)
    ]
    assert np.allclose(exact, [1.875104, 4.694091, 7.854757], atol=5e-7)
    beta = _beta(m)
    rel = np.abs(beta**2 / np.repeat(exact, 2) ** 2 - 1)  # frequency ~ beta^2
    # 1e-6 relative in the frequency: the goal; the estimate must cover the error
    assert rel.max() < 1e-6, rel
    assert np.all(rel <= np.maximum(m.accuracy, 1e-9) * 3), (rel, m.accuracy)
    # two planes of the round rod: the same frequency twice, to round-off of the solve
    assert np.allclose(m.omega2[0::2], m.omega2[1::2], rtol=1e-9)
    # the two shapes of a pair lie in orthogonal planes
    for k in (0, 2, 4):
        a, b = m.shape_position[k][-1, :2], m.shape_position[k + 1][-1, :2]
        assert abs(a @ b) < 1e-6 * np.linalg.norm(a) * np.linalg.norm(b)


def test_shapes_normalised_and_modal_mass():
    m = tr.modes(_cantilever(), n=2, options=EB)
    amp = np.linalg.norm(m.shape_position, axis=2).max(axis=1)
    assert np.allclose(amp, 1.0, rtol=1e-12)  # the stated normalisation
    # the first Euler-Bernoulli mode normalised to a unit tip displacement has modal mass
    # rho A L / 4 (int phi^2 ds = L/4 for the cantilever's first mode); to the grid's
    # trapezoid-rule error at 96 elements (~1e-4) and the shape's extrapolation-free value
    assert m.modal_mass[0] == pytest.approx(RHO * A * L / 4, rel=1e-3)
    assert m.s[0] == 0 and m.s[-1] == L and np.all(np.diff(m.s) > 0)
    assert np.allclose(m.shape_position[:, 0], 0) and np.allclose(m.shape_rotation[:, 0], 0)


# ---------------------------------------------------------------- rotary inertia, shear
def test_rayleigh_beam_kirchhoff_rod_with_rotary_inertia():
    # a stubby rod (L/d = 20): the rotary inertia lowers the frequencies by ~1e-3
    d = 1e-2
    m = tr.modes(_cantilever(d=d), n=6)
    a, i = math.pi * d**2 / 4, math.pi * d**4 / 64
    for k in _bending(m)[::2]:
        om = math.sqrt(m.omega2[k])
        ref = _beam_root(om, EI=E * i, rhoA=RHO * a, rhoI=RHO * i)
        # 1e-6 relative: the goal (the reference is to ~1e-11)
        assert abs(om / ref - 1) < 1e-6, (k, om / ref - 1)


def test_timoshenko_beam_cosserat_rod():
    d = 1e-2
    m = tr.modes(_cantilever(kirchhoff=False, d=d), n=6)
    a, i = math.pi * d**2 / 4, math.pi * d**4 / 64
    ks = _bending(m)
    assert len(ks) >= 4
    for k in ks[::2]:
        om = math.sqrt(m.omega2[k])
        ref = _beam_root(om, EI=E * i, rhoA=RHO * a, rhoI=RHO * i, GA=G * a)
        eb = [1.875104, 4.694091, 7.854757][ks.index(k) // 2] ** 2 * math.sqrt(
            E * i / (RHO * a * L**4)
        )
        # the Timoshenko correction is of order (d/L)^2 (beta L)^2 (E/G + 1) / 16:
        # visible (> 1e-4) and bounded, and the model matches the exact Timoshenko
        # frequency to the goal 1e-6
        assert 1e-4 < 1 - ref / eb < 0.1
        assert abs(om / ref - 1) < 1e-6, (k, om / ref - 1)


def test_first_torsional_frequency():
    # d = 1 cm: the first torsional mode (3993 Hz, whatever d) is the 7th (bending 180,
    # 1129, 3159 Hz, each twice)
    m = tr.modes(_cantilever(kirchhoff=False, d=1e-2), n=8)
    tors = [
        k
        for k in range(m.n)
        if L * np.abs(m.shape_rotation[k][:, 2]).max() > 0.99
        and np.abs(m.shape_position[k]).max() < 1e-6
    ]
    assert len(tors) == 1
    # omega = (pi / 2L) sqrt(GJ / (rho J)) = (pi / 2L) sqrt(G / rho)
    exact = math.pi / (2 * L) * math.sqrt(G / RHO)
    om = math.sqrt(m.omega2[tors[0]])
    assert abs(om / exact - 1) < 1e-6  # the goal
    # the shape: sin(pi s / 2L) about the axis
    phi = m.shape_rotation[tors[0]][:, 2] * L
    assert np.allclose(phi, np.sin(np.pi * m.s / (2 * L)), atol=1e-6)


# ---------------------------------------------------------------- tip mass, tension
@pytest.mark.parametrize("mu", [0.25, 1.0])
def test_tip_point_mass(mu):
    M = mu * RHO * A * L
    m = tr.modes(_cantilever(loads=[tr.PointMass(s=L, mass=M)]), n=2, options=EB)
    b = _beta(m)[0]

    def g(x):
        c, s, ch, sh = math.cos(x), math.sin(x), math.cosh(x), math.sinh(x)
        return 1 + c * ch + mu * x * (c * sh - s * ch)

    exact = brentq(g, 0.5, 1.875104, xtol=1e-15)
    assert abs(b**2 / exact**2 - 1) < 1e-6  # the goal, on the frequency


def test_axially_tensioned_cantilever():
    # a dead tension T at the tip: EI w'''' - T w'' = rho A omega^2 w, w(0) = w'(0) = 0,
    # w''(L) = 0, EI w'''(L) = T w'(L); the exact 4 x 4 determinant of its
    # cosh/sinh/cos/sin solution, its roots by brentq
    EI, rA = E * I, RHO * A
    T = 20 * EI / L**2
    m = tr.modes(_cantilever(loads=[tr.PointLoad(s=L, force=(0, 0, T))]), n=4, options=EB)

    def det(om):
        r = math.sqrt(T**2 + 4 * EI * rA * om**2)
        a, b = math.sqrt((T + r) / (2 * EI)), math.sqrt((r - T) / (2 * EI))
        # w = c1 cosh as + c2 sinh as + c3 cos bs + c4 sin bs
        ch, sh, c, s = math.cosh(a * L), math.sinh(a * L), math.cos(b * L), math.sin(b * L)
        Mx = np.array(
            [
                [1, 0, 1, 0],
                [0, a, 0, b],
                [a * a * ch, a * a * sh, -b * b * c, -b * b * s],
                [
                    EI * a**3 * sh - T * a * sh,
                    EI * a**3 * ch - T * a * ch,
                    EI * b**3 * s + T * b * s,
                    -EI * b**3 * c - T * b * c,
                ],
            ]
        )
        return np.linalg.det(Mx / np.abs(Mx).max(axis=1, keepdims=True))

    for k in (0, 2):
        om = math.sqrt(m.omega2[k])
        ref = brentq(det, 0.99 * om, 1.01 * om, xtol=1e-13 * om)
        assert abs(om / ref - 1) < 1e-6, om / ref - 1  # the goal
    # stiffened: above the free cantilever's
    free = 1.875104**2 * math.sqrt(EI / (rA * L**4))
    assert math.sqrt(m.omega2[0]) > 1.2 * free


# ---------------------------------------------------------------- the robot
def _robot_scene(q, control):
    rod = tr.Rod(L, 1e-3, E, G, density=RHO, kirchhoff=True)
    tendon = tr.Tendon(offset=0.005, EA=500.0)
    robot = tr.Robot(rod, [tendon])
    if control == "displacement":
        return tr.Scene(robot, displacement=[q])
    return tr.Scene(robot, tension=[q])


def _ritz_bound(EI, rhoA, k, r, nz=8):
    """Rayleigh-Ritz from the paper's closed forms: the static shapes of unit lateral
    forces at z = L/nz ... L (analytic.deflection, a parallel tendon held by a spring k) as
    the basis; stiffness c^T W c with W_ij = w_i(z_j) (Maxwell), mass int rho A w_i w_j."""
    z = L * np.arange(1, nz + 1) / nz
    s = np.linspace(0, L, 4001)
    W = np.array([analytic.deflection(s, 1.0, zi, L, EI, 0.0, r, k) for zi in z])
    Kf = np.array([[analytic.deflection(zj, 1.0, zi, L, EI, 0.0, r, k) for zj in z] for zi in z])
    # Simpson on the fine grid (the shapes are cubic pieces: its error ~1e-15)
    wts = np.full(s.size, 2.0)
    wts[1::2], wts[0], wts[-1] = 4.0, 1.0, 1.0
    Mm = rhoA * (W * wts) @ W.T * (s[1] - s[0]) / 3
    from scipy.linalg import eigh

    return eigh(0.5 * (Kf + Kf.T), Mm, eigvals_only=True)[0]


def test_servo_held_robot_against_closed_form_ritz():
    rod = tr.Rod(L, 1e-3, E, G, density=RHO, kirchhoff=True)
    EI, rA = rod.bending_stiffness, rod.mass_per_length
    r, k = 0.005, 500.0 / L  # the tendon's stretch stiffness EA / l
    bound = _ritz_bound(EI, rA, k, r, nz=16)
    free = 1.875104**4 * EI / (rA * L**4)
    assert bound > 1.5 * free  # the tendon stiffens the robot in its plane
    diffs = []
    for q in (1e-5, 1e-6):
        m = tr.modes(_robot_scene(q, "displacement"), n=2, options=EB)
        # the in-plane mode (the tendon's plane x-z) is the stiffened one: the second
        inplane = max(range(2), key=lambda j: abs(m.shape_position[j][-1, 0]))
        w2 = m.omega2[inplane]
        diffs.append(abs(w2 / bound - 1))
        # Rayleigh-Ritz bounds from above (up to the actuation's O(q) change)
        assert w2 < bound * (1 + 1e-4)
    # converging as the actuation (load) goes to zero, to the Ritz basis's own error
    # (measured at q = 1e-6: 8 static shapes 1.0e-5 of omega^2, 16 shapes 9.7e-7, 32
    # shapes 4.9e-7) -- within 2e-6 with 16
    assert diffs[-1] < 2e-6, diffs


def test_displacement_held_at_least_tension_held():
    sd = tr.solve(_robot_scene(2e-4, "displacement"))
    tau = float(sd.tendon_tension[0, 0])
    st = tr.solve(_robot_scene(tau, "tension"))
    # the same equilibrium (same tension): the tip agrees to the solver's tolerance
    assert np.allclose(sd.tip_position, st.tip_position, atol=1e-8)
    md, mt = tr.modes(sd, n=6), tr.modes(st, n=6)
    # the held tendon adds (EA/l) g g^T >= 0 to the stiffness: every eigenvalue rises or
    # stays (interlacing); the extrapolated values keep it to their accuracy
    slack = 3 * (md.accuracy + mt.accuracy) * md.omega2
    assert np.all(md.omega2 >= mt.omega2 - slack)
    assert md.omega2.max() > mt.omega2.max() or md.omega2[1] > 1.5 * mt.omega2[1]


# ---------------------------------------------------------------- the verdict
def test_lowest_frequency_vanishes_at_the_bifurcation_path_finds():
    rod = tr.Rod(L, D, E, G, density=RHO, kirchhoff=True)
    PE = math.pi**2 * rod.bending_stiffness / (4 * L**2)
    scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L, force=(0, 0, 0))])
    p = tr.path(scene, "loads[0].force[2]", (0.0, -2.0 * PE))
    sp = p.special_points[0]
    assert sp.kind == "bifurcation"
    Pc = -sp.value
    w2 = []
    for eps in (1e-2, 1e-3):
        sc = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L, force=(0, 0, -(1 - eps) * Pc))])
        w2.append(tr.modes(sc, n=1).omega2[0])
    w0 = tr.modes(_cantilever(), n=1).omega2[0]
    # omega^2 vanishes linearly at Pc: a tenth of the distance, a tenth of omega^2 (to the
    # curvature of omega^2(P) and the path's location of Pc, ~3e-3 of P_E here)
    assert w2[0] < 0.05 * w0
    assert w2[1] / w2[0] == pytest.approx(0.1, rel=0.05)


def test_unstable_refused_unless_allowed():
    rod = tr.Rod(L, D, E, G, density=RHO, kirchhoff=True)
    PE = math.pi**2 * rod.bending_stiffness / (4 * L**2)
    sc = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L, force=(0, 0, -1.5 * PE))])
    sol = tr.solve(sc, options=tr.Options(accept_unstable=True))
    assert sol.stable is False
    with pytest.warns(tr.ConvergenceWarning, match="unstable"):
        m = tr.modes(sol)
    assert not m.success and m.status == tr._core.STATUS_UNSTABLE
    with pytest.raises(tr.ConvergenceError):
        tr.modes(sol, strict=True)
    m = tr.modes(sol, n=3, allow_unstable=True)
    assert m.success and m.omega2[0] < 0 and m.omega2[1] < 0 < m.omega2[2]
    assert np.iscomplexobj(m.frequencies) and m.frequencies[0].real == 0


def test_bad_input():
    sc = _cantilever()
    with pytest.raises(ValueError, match="n must be"):
        tr.modes(sc, n=0)
    with pytest.raises(ValueError, match="elements"):
        tr.modes(sc, options={"elements": 1})
    with pytest.raises(ValueError, match="no key 'grid'"):
        tr.modes(sc, options={"grid": 3})
    with pytest.raises(ValueError, match="no mass"):
        tr.modes(tr.Scene(tr.Robot(tr.Rod(L, D, E, G), [])))
    with pytest.raises(TypeError, match="Scene or a Solution"):
        tr.modes(3.0)


def test_result_protocol_and_repr():
    m = tr.modes(_cantilever(), n=2)
    assert isinstance(m, tr.Result)
    assert m.nit > 0 and m.nfev > 0 and m.status == 0
    assert "Modes(n=2" in repr(m) and "Hz" in repr(m)
    # work is bounded by counting: at most TR_MODES_SWEEPS sweeps per grid
    assert m.nit <= 3 * 300


def test_plot_modes():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = tr.modes(_cantilever(), n=4)
    plt.close("all")
    ax = tr.plot.modes(m)
    # the equilibrium and two lines (+-) per mode of the first three
    assert len(ax.lines) == 1 + 2 * 3
    fig, given = plt.subplots()
    assert tr.plot.modes(m, which=[3], ax=given) is given and len(given.lines) == 3
    assert tr.plot.modes(m, plane="3d").name == "3d"
    with pytest.raises(ValueError, match="which"):
        tr.plot.modes(m, which=[7])
    with pytest.raises(ValueError, match="plane"):
        tr.plot.modes(m, plane="zz")
    plt.close("all")


def test_damping_ratio_kelvin_voigt():
    eta = 1e-5  # [s]
    rod = tr.Rod(L, D, E, G, density=RHO, kirchhoff=True, damping=eta)
    m = tr.modes(tr.Scene(tr.Robot(rod, [])), n=2)
    # an unloaded rod: C = eta K exactly, zeta = eta omega / 2
    assert np.allclose(m.damping_ratio, eta * np.sqrt(m.omega2) / 2, rtol=1e-12)
    assert tr.modes(_cantilever(), n=1).damping_ratio is None
    with pytest.raises(ValueError, match="Rod.damping must be >= 0"):
        tr.Rod(L, D, E, G, damping=-1.0)


def test_mounted_robot_shapes_in_the_world_frame():
    rod = tr.Rod(L, D, E, G, density=RHO, kirchhoff=True)
    R0 = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # base z along +x
    p0 = np.array([0.1, 0.2, 0.3])
    mounted = tr.Scene(tr.Robot(rod, [], base_position=p0, base_rotation=R0))
    a, b = tr.modes(_cantilever(), n=2), tr.modes(mounted, n=2)
    # no gravity: the same robot, the same frequencies (to round-off), its shapes rotated
    assert np.allclose(a.omega2, b.omega2, rtol=1e-10)
    assert np.allclose(b.position, p0 + a.position @ R0.T, atol=1e-12)
    assert np.allclose(
        np.abs(b.shape_position[:, -1] @ R0), np.abs(a.shape_position[:, -1]), atol=1e-9
    )


def test_friction_refused():
    rod = tr.Rod(L, 1e-3, E, G, density=RHO, kirchhoff=True)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.005, friction=0.1)])
    sol = tr.solve(tr.Scene(robot, tension=[1.0]))
    with pytest.warns(tr.ConvergenceWarning, match="channel friction"):
        m = tr.modes(sol)
    assert not m.success and "friction=0" in m.message


def test_save_load(tmp_path):
    m = tr.modes(_cantilever(), n=3)
    m.save(tmp_path / "m.npz")
    back = tr.Modes.load(tmp_path / "m.npz")
    assert back.success and back.message == m.message and back.nit == m.nit
    for name in ("frequencies", "omega2", "accuracy", "shape_position", "shape_rotation"):
        assert np.array_equal(getattr(back, name), getattr(m, name))  # bit for bit
    np.savez(tmp_path / "x.npz", a=np.zeros(2))
    with pytest.raises(ValueError, match="not a file written by Modes.save"):
        tr.Modes.load(tmp_path / "x.npz")


def test_self_weight_hanging_stiffer_than_standing():
    # gravity along the rod: hanging (tension from the weight) rings faster than free,
    # standing (compression) slower; at a tenth of the self-weight buckling load
    # (7.84 EI/L^3 per length), the first frequency moves by ~0.1 of itself
    rod = tr.Rod(L, D, E, G, density=RHO, kirchhoff=True)
    q_cr = 7.837 * rod.bending_stiffness / L**3
    g = 0.1 * q_cr / rod.mass_per_length

    def first(gz):
        return tr.modes(tr.Scene(tr.Robot(rod, []), gravity=(0, 0, gz)), n=1).omega2[0]

    hanging, free, standing = first(g), first(0.0), first(-g)
    assert standing < free < hanging
    assert 0.02 < 1 - standing / free < 0.3 and 0.02 < hanging / free - 1 < 0.3


def test_tendons_at_their_switch_vibrate_slack():
    rod = tr.Rod(L, 1e-3, E, G, density=RHO, kirchhoff=True)
    robot = tr.Robot(rod, tr.Tendon.ring(3, 0.005, EA=2e3))
    m = tr.modes(tr.Scene(robot, displacement=[0.0, 0.0, 0.0]), n=2)
    bare = tr.modes(tr.Scene(tr.Robot(rod, []), displacement=[]), n=2)
    assert "[0, 1, 2] at their taut/slack switch" in m.message
    # slack: the bare rod's frequencies (the tendons add no mass); same grids, same values
    assert np.allclose(m.omega2, bare.omega2, rtol=1e-12)
