"""tr.solve_batch: batch solves of one design against individual tr.solve calls and
closed forms; failure isolation, argument checking, determinism, threads."""

import dataclasses
import math
import threading
import warnings

import numpy as np
import pytest

import tendonrod as tr

L = 0.2
ROD = tr.Rod(length=L, diameter=0.8e-3, E=207e9, G=79.6e9)
EI = ROD.bending_stiffness
R_OFF = 0.01

# Accuracy of one solve: the scaled residual is converged to tol = 1e-10 and automatic
# steps are verified to the same level, which puts the tip within ~1e-10..1e-9 L of the
# exact equilibrium; two independent solves (different starts) may each sit anywhere in
# that band, so they are compared at 1e-8 L (10x above it, far below any physical
# difference).
TIP_TOL = 1e-8 * L


def planar_scene():
    """One displacement-controlled tendon (x-z plane), a tip load."""
    robot = tr.Robot(ROD, [tr.Tendon(offset=R_OFF, angle=0.0)])
    return tr.Scene(robot, displacement=[0.004], loads=[tr.PointLoad(s=L, force=(0, 0, 0))])


def spatial_scene():
    """Three tendons at 120 deg: tendon 0 retracted to a ~90 deg bend, the other two
    tension-controlled (zero tension); a tip load and a mid-length load."""
    tens = [tr.Tendon(offset=R_OFF, angle=2 * math.pi * i / 3) for i in range(3)]
    return tr.Scene(
        tr.Robot(ROD, tens),
        displacement=[R_OFF * math.pi / 2, None, None],
        tension=[None, 0.0, 0.0],
        loads=[tr.PointLoad(s=L, force=(0, 0, 0)), tr.PointLoad(s=L / 2, force=(0, 0, 0))],
    )


def with_point(scene, forces=None, moments=None, displacement=None, tension=None):
    """The scene of one batch point, built the ordinary way (for tr.solve)."""
    loads, k = [], 0
    for ld in scene.loads:
        if isinstance(ld, tr.PointLoad):
            f = ld.force if forces is None else tuple(forces[k])
            mo = ld.moment if moments is None else tuple(moments[k])
            loads.append(dataclasses.replace(ld, force=f, moment=mo))
            k += 1
        else:
            loads.append(ld)
    kw = {"loads": loads}
    ctl = scene.displacement_controlled()
    if displacement is not None or tension is not None:
        it_d = iter(displacement if displacement is not None else [])
        it_t = iter(tension if tension is not None else [])
        disp = [
            (float(next(it_d)) if displacement is not None else scene.displacement[i])
            if c
            else None
            for i, c in enumerate(ctl)
        ]
        ten = [
            None if c else (float(next(it_t)) if tension is not None else scene.tension[i])
            for i, c in enumerate(ctl)
        ]
        kw.update(displacement=disp, tension=ten)
    return dataclasses.replace(scene, **kw)


def test_planar_forces_match_individual_solves():
    scene = planar_scene()
    n = 12
    F = np.zeros((n, 1, 3))
    F[:, 0, 0] = np.linspace(-0.3, 0.3, n)
    F[:, 0, 2] = -0.05
    res = tr.solve_batch(scene, forces=F)
    assert res.success.all(), res.failures()
    assert res.formulation["planar"]
    assert res.tip_position.shape == (n, 3) and res.tip_rotation.shape == (n, 3, 3)
    assert res.cold.tolist() == [True] + [False] * (n - 1)
    for p in range(n):
        sol = tr.solve(with_point(scene, forces=F[p]), options=tr.Options(tip_only=True))
        np.testing.assert_allclose(res.tip_position[p], sol.tip_position, rtol=0, atol=TIP_TOL)
        np.testing.assert_allclose(res.tip_rotation[p], sol.tip_rotation, rtol=0, atol=1e-8)
        # tension [N]: relative to the load scale EI/(r L) (~2 N), same 1e-8 band
        np.testing.assert_allclose(
            res.tension[p], sol.tension, rtol=0, atol=1e-8 * EI / (R_OFF * L)
        )
        np.testing.assert_allclose(res.displacement[p], sol.displacement, rtol=0, atol=1e-12)
    assert all("converged" in m for m in res.message)


@pytest.mark.parametrize("steps", [0, 6])
def test_spatial_loads_and_actuation_match_individual_solves(steps):
    scene = spatial_scene()
    n = 10
    rng = np.random.default_rng(7)
    F = np.zeros((n, 2, 3))
    F[:, 0, :2] = np.cumsum(rng.uniform(-0.02, 0.02, (n, 2)), axis=0)  # a random walk
    M = np.zeros((n, 2, 3))
    M[:, 1, 2] = np.linspace(0.0, 2e-3, n)  # twist at mid-length
    q = np.linspace(0.9, 1.1, n)[:, None] * (R_OFF * math.pi / 2)
    tau = np.column_stack([np.linspace(0.0, 0.1, n), np.zeros(n)])
    opts = tr.Options(steps=steps)
    res = tr.solve_batch(scene, forces=F, moments=M, displacement=q, tension=tau, options=opts)
    assert res.success.all(), res.failures()
    assert not res.formulation["planar"]
    for p in range(n):
        sc = with_point(scene, forces=F[p], moments=M[p], displacement=q[p], tension=tau[p])
        sol = tr.solve(sc, options=dataclasses.replace(opts, tip_only=True))
        np.testing.assert_allclose(res.tip_position[p], sol.tip_position, rtol=0, atol=TIP_TOL)
        np.testing.assert_allclose(
            res.tension[p], sol.tension, rtol=0, atol=1e-8 * EI / (R_OFF * L)
        )
        np.testing.assert_allclose(res.slack[p], sol.slack, rtol=0, atol=1e-8 * L)
        # the prescribed values come back as given
        assert res.displacement[p, 0] == q[p, 0]
        assert res.tension[p, 1] == tau[p, 0]


def test_grid_swept_line_by_line_starts_each_line_next_to_the_last():
    """A tip-force grid in one chunk, swept line by line (F_y fastest): each line's first
    point lies one grid step from the previous line's first point but a whole line
    (0.2 N, ~FL^2/EI = 4) from the previous point.  Every point matches its own cold
    solve, verdicts included, and a line's first point is started next to it: it costs
    no more residual evaluations than a line's second point (also a plain warm start,
    one grid step away, without a predictor)."""
    scene = spatial_scene()
    m = 6
    f = np.linspace(-0.1, 0.1, m)
    F = np.zeros((m * m, 2, 3))
    F[:, 0, 0] = np.repeat(f, m)
    F[:, 0, 1] = np.tile(f, m)
    opts = tr.Options(steps=6)
    res = tr.solve_batch(scene, forces=F, options=opts)
    assert res.success.all(), res.failures()
    assert res.cold.sum() == 1
    for p in range(0, m * m, 5):
        sol = tr.solve(
            with_point(scene, forces=F[p]), options=dataclasses.replace(opts, tip_only=True)
        )
        np.testing.assert_allclose(res.tip_position[p], sol.tip_position, rtol=0, atol=TIP_TOL)
        assert res.stable[p] == sol.stable
    first = res.nfev[m::m]  # lines 2.., first point
    second = res.nfev[m + 1 :: m]
    # counts, not timings: a start one grid step away needs the same few Newton steps
    # (the far start of the previous line's last point took tens of iterations)
    assert first.max() <= second.max(), (first, second)


def test_pure_end_moment_is_an_exact_circle():
    """A plain rod under a tip moment M bends into a circular arc of curvature M/EI
    (no internal force, so shear and extension stay zero): tip (1 - cos k L)/k, sin(k L)/k.
    Integration truncation (rk8, verified steps) keeps the tip within ~1e-10 L."""
    scene = tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(s=L, moment=(0, 0, 0))])
    theta = np.linspace(0.1, 1.5 * math.pi, 15)  # bend angle k L
    M = np.zeros((theta.size, 1, 3))
    M[:, 0, 1] = theta * EI / L
    res = tr.solve_batch(scene, moments=M)
    assert res.success.all(), res.failures()
    k = theta / L
    np.testing.assert_allclose(
        np.abs(res.tip_position[:, 0]), (1 - np.cos(k * L)) / k, rtol=0, atol=1e-9 * L
    )
    np.testing.assert_allclose(res.tip_position[:, 2], np.sin(k * L) / k, rtol=0, atol=1e-9 * L)
    np.testing.assert_allclose(res.tip_position[:, 1], 0.0, atol=1e-15)


def test_failed_point_is_isolated_with_its_message():
    scene = planar_scene()
    n = 9
    F = np.zeros((n, 1, 3))
    F[:, 0, 0] = np.linspace(0.0, 0.2, n)
    F[4, 0, 0] = 1e4  # FL^2/EI ~ 1e5: no converged solve within these caps
    opts = tr.Options(continuation=False, max_iter=15, max_nfev=200)
    with pytest.raises(tr.ConvergenceError, match="1 of 9 points did not succeed") as err:
        tr.solve_batch(scene, forces=F, options=opts, strict=True)
    assert isinstance(err.value.solution, tr.BatchResult)
    with pytest.warns(tr.ConvergenceWarning, match=r"the first: \(4, "):
        res = tr.solve_batch(scene, forces=F, options=opts)
    assert res.status[4] < 0 and not res.success[4]
    assert res.message[4] and "converged in" not in res.message[4]
    assert [i for i, _, _ in res.failures()] == [4]
    good = [p for p in range(n) if p != 4]
    assert res.success[good].all()
    for p in (3, 5, 8):  # the neighbours of the failed point are unaffected
        sol = tr.solve(with_point(scene, forces=F[p]), options=tr.Options(tip_only=True))
        np.testing.assert_allclose(res.tip_position[p], sol.tip_position, rtol=0, atol=TIP_TOL)


@pytest.mark.parametrize(
    "kw, name",
    [
        ({"forces": np.zeros((4, 2, 3))}, "forces"),  # scene has one point load
        ({"forces": np.zeros((4, 3))}, "forces"),
        ({"moments": np.zeros((4, 1, 2))}, "moments"),
        ({"displacement": np.zeros((4, 2))}, "displacement"),  # one displacement-controlled tendon
        ({"tension": np.zeros((4, 1))}, "tension"),  # none tension-controlled
        ({"distributed": np.zeros((4, 2))}, "distributed"),
        (
            {"forces": np.zeros((4, 1, 3)), "displacement": np.zeros((5, 1))},
            r"forces must have shape \(5, 1, 3\)",
        ),
        ({"forces": np.full((2, 1, 3), np.nan)}, "forces"),
        ({}, "at least one"),
        ({"forces": np.zeros((2, 1, 3)), "workers": 0}, "workers"),
        ({"forces": np.zeros((2, 1, 3)), "chunksize": 0}, "chunksize"),
    ],
)
def test_bad_arguments_are_named(kw, name):
    with pytest.raises(ValueError, match=name):
        tr.solve_batch(planar_scene(), **kw)


def test_negative_tension_is_named():
    with pytest.raises(ValueError, match=r"tension.*>= 0"):
        tr.solve_batch(spatial_scene(), tension=np.array([[0.1, -1.0]]))


def test_out_of_plane_points_switch_the_whole_batch_to_spatial():
    scene = planar_scene()
    F = np.zeros((4, 1, 3))
    F[:, 0, 0] = 0.1
    F[2, 0, 1] = 0.05  # one point leaves the x-z plane
    res = tr.solve_batch(scene, forces=F)
    assert not res.formulation["planar"] and res.success.all()
    for p in (1, 2):
        sol = tr.solve(with_point(scene, forces=F[p]), options=tr.Options(tip_only=True))
        np.testing.assert_allclose(res.tip_position[p], sol.tip_position, rtol=0, atol=TIP_TOL)


def test_deterministic_and_independent_of_threads():
    scene = spatial_scene()
    n = 24
    F = np.zeros((n, 2, 3))
    F[:, 0, 0] = np.linspace(-0.1, 0.1, n)
    a = tr.solve_batch(scene, forces=F, chunksize=6)
    b = tr.solve_batch(scene, forces=F, chunksize=6)
    c = tr.solve_batch(scene, forces=F, chunksize=6, workers=2)
    for r in (b, c):
        assert np.array_equal(a.tip_position, r.tip_position)  # bitwise
        assert np.array_equal(a.tension, r.tension)
        assert np.array_equal(a.nit, r.nit)
    assert a.cold.sum() == 4  # one cold start per chunk
    # another chunking gives the same equilibria to the solver tolerance
    d = tr.solve_batch(scene, forces=F, chunksize=24)
    np.testing.assert_allclose(a.tip_position, d.tip_position, rtol=0, atol=TIP_TOL)


def test_concurrent_calls_from_python_threads():
    scene = spatial_scene()
    F = np.zeros((16, 2, 3))
    F[:, 0, 1] = np.linspace(0.0, 0.1, 16)
    ref = tr.solve_batch(scene, forces=F)
    out = [None] * 4

    def work(i):
        out[i] = tr.solve_batch(scene, forces=F)

    ts = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    for r in out:
        assert np.array_equal(r.tip_position, ref.tip_position)


def test_value_dependent_scene_is_checked_per_point():
    """Opposing inextensible displacement-controlled tendons on a Kirchhoff rod: whether a
    point has a unique equilibrium depends on the displacements, which the core checks again
    whenever a point's values are set; the 'no equilibrium' point (both retracted) fails
    alone, the others (net release, sum q < 0) solve and match single solves."""
    rod = dataclasses.replace(ROD, kirchhoff=True)
    robot = tr.Robot(
        rod, [tr.Tendon(offset=R_OFF, angle=0.0), tr.Tendon(offset=R_OFF, angle=math.pi)]
    )
    scene = tr.Scene(robot, displacement=[0.002, -0.003])
    q = np.array([[0.002, -0.003], [0.003, -0.004], [0.001, 0.001], [0.004, -0.005]])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        res = tr.solve_batch(scene, displacement=q)
    assert res.success.tolist() == [True, True, False, True]
    assert "equilibrium" in res.message[2]
    for p in (0, 3):
        sol = tr.solve(with_point(scene, displacement=q[p]), options=tr.Options(tip_only=True))
        np.testing.assert_allclose(res.tip_position[p], sol.tip_position, rtol=0, atol=TIP_TOL)


def test_sweep_uses_the_batch_path_bitwise(monkeypatch):
    """tr.sweep over load and actuation values goes through solve_batch in exact mode:
    no per-point tr.solve runs, and the records equal the per-point loop bit for bit."""
    import tendonrod._core as core

    scene = spatial_scene()
    forces = [(fx, 0.02, 0.0) for fx in np.linspace(-0.05, 0.05, 5)]
    qs = [R_OFF * math.pi / 2 * f for f in (0.95, 1.0)]
    opts = tr.Options(tip_only=True)
    # the reference: the per-point loop, warm-started within each chunk (one grid line)
    ref = []
    for q in qs:
        guess = None
        for f in forces:
            sc = with_point(scene, forces=[f, (0, 0, 0)], displacement=[q])
            sol = tr.solve(sc, guess=guess, options=opts)
            ref.append(sol)
            guess = sol if sol.success else guess
    # every per-point solve compiles a _core.Problem (tr.solve is a one-shot Problem)
    calls = []
    real = core.Problem
    monkeypatch.setattr(core, "Problem", lambda *a, **k: calls.append(1) or real(*a, **k))
    res = tr.sweep(
        scene, {"displacement[0]": qs, "loads[0].force": forces}, progress=False, workers=2
    )
    assert not calls  # every chunk went through the batch
    tr.solve(scene, options=opts)
    assert len(calls) == 1  # the probe sees a per-point solve
    assert res.success.all()
    tip = res["tip_position"].reshape(-1, 3)
    ten = res["tension"].reshape(-1, 3)
    for p, sol in enumerate(ref):
        assert np.array_equal(tip[p], sol.tip_position)
        assert np.array_equal(ten[p], sol.tension)


def test_lean_loop_without_recording_pass():
    """Fixed steps: the lean loop's tip read from its last residual evaluation equals the
    recorded tip (the recording pass replaces its tip by the shooting tip, so up to
    round-off; 1e-12 L); only the displacement of tension-controlled tendons is lost (NaN
    where the lean loop solved), and it saves one integration per point."""
    scene = spatial_scene()
    n = 30
    F = np.zeros((n, 2, 3))
    F[:, 0, 0] = np.linspace(-0.05, 0.05, n)
    F[:, 0, 1] = 0.01
    opts = tr.Options(steps=4, tol=3e-9)
    a = tr.solve_batch(scene, forces=F, options=opts)
    b = tr.solve_batch(scene, forces=F, options=opts, tension_tendon_displacement=False)
    assert a.success.all() and b.success.all()
    np.testing.assert_allclose(b.tip_position, a.tip_position, rtol=0, atol=1e-12 * L)
    np.testing.assert_allclose(b.tension, a.tension, rtol=0, atol=1e-12 * EI / (R_OFF * L))
    lean = ~b.cold
    assert lean.sum() >= n - 2
    assert np.isnan(b.displacement[lean][:, 1:]).all()
    assert np.array_equal(b.displacement[:, 0], a.displacement[:, 0])  # prescribed q
    assert b.nfev[lean].sum() < a.nfev[lean].sum()
    # the lean loop reaches the tolerance it was given (scaled residual max-norm)
    assert np.all(b.residual_norm <= 3e-9)
    # and agrees with individual fixed-step solves to that tolerance (tip within ~tol L)
    for p in (1, 15, 29):
        sol = tr.solve(
            with_point(scene, forces=F[p]), options=dataclasses.replace(opts, tip_only=True)
        )
        np.testing.assert_allclose(b.tip_position[p], sol.tip_position, rtol=0, atol=TIP_TOL)


def test_all_displacement_controlled_scene_keeps_displacements():
    """With every tendon displacement-controlled nothing needs the recording pass: the
    lean loop skips it and the displacements are the prescribed ones."""
    scene = planar_scene()
    q = np.linspace(0.002, 0.006, 20)[:, None]
    res = tr.solve_batch(scene, displacement=q, options=tr.Options(steps=6))
    assert res.success.all()
    assert np.array_equal(res.displacement, q)
    for p in (3, 19):
        sol = tr.solve(
            with_point(scene, displacement=q[p]), options=tr.Options(steps=6, tip_only=True)
        )
        np.testing.assert_allclose(res.tip_position[p], sol.tip_position, rtol=0, atol=TIP_TOL)


def test_degenerate_arrays():
    """No points: an empty result; strings and complex numbers: refused by name."""
    res = tr.solve_batch(planar_scene(), displacement=np.zeros((0, 1)))
    assert len(res) == 0 and res.tip_position.shape == (0, 3) and res.message.shape == (0,)
    for bad in (np.array([["abc"]]), np.array([[0.001 + 0.5j]])):
        with pytest.raises(ValueError, match="displacement must be an array of real numbers"):
            tr.solve_batch(planar_scene(), displacement=bad)


def test_sweep_with_fixed_steps_uses_the_lean_loop():
    """With a fixed step count the sweep's chunks run the batch's lean loop: equal to the
    per-point loop to the solver tolerance (not bitwise), fewer integrations."""
    scene = spatial_scene()
    forces = [(fx, 0.01, 0.0) for fx in np.linspace(-0.05, 0.05, 12)]
    opts = tr.Options(steps=6, tip_only=True)
    res = tr.sweep(
        scene, {"loads[0].force": forces}, grid=False, chunksize=12, options=opts, progress=False
    )
    assert res.success.all()
    guess, loop_nit = None, 0
    for p, f in enumerate(forces):
        sol = tr.solve(with_point(scene, forces=[f, (0, 0, 0)]), guess=guess, options=opts)
        guess = sol
        loop_nit += sol.nit
        np.testing.assert_allclose(res["tip_position"][p], sol.tip_position, rtol=0, atol=TIP_TOL)
        np.testing.assert_allclose(res["displacement"][p], sol.displacement, rtol=0, atol=1e-8 * L)
    assert res.nit.sum() < loop_nit  # predictor + carried Jacobian: fewer iterations
