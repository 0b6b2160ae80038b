"""The loop that bench/valgrind.sh runs under valgrind memcheck.

    python bench/valgrind_loop.py [--fast] [--solves N] [--ufuncs N]

Exercises every path of the glue and the core that a user reaches:
- the closed-form ufuncs on scalars, arrays, out=/where=, NaN input, and the
  TypeError path;
- tr.solve on scenes that converge (planar/spatial, Kirchhoff/Cosserat,
  displacement/tension control, point and distributed loads, two segments, channel
  friction with a curvature reversal and a mid-length anchor, tr.slip),
  warm starts from a previous solution, tip_only, explicit nodes, every
  integrator, sol.at(s), sol.stable, tr.compliance;
- solves that fail (iteration cap, impossible displacement) and raise with
  strict=True;
- the raw _core.solve with wrong shapes, dtypes and option values (the error
  paths of the glue, where a missing free or Py_DECREF hides);
- tr.solve_batch on two threads, with failing points among good ones;
- tr.Problem: values set per call, warm solves, guess modes, another structure (the
  ValueError path), compliance from the kept state, pickling; an equilibrium found off
  the load path and confirmed by the second formulation (allocated on first need); the
  work budget running out; a Cancel token stopping a solve on a thread;
- tr.actuate (its run in C): least change, square, least squares, tension controls, an
  unreachable target, the glue's and the QP's error paths.
Every call's outcome is checked lightly (so a wrong turn is noticed), the
point is what valgrind sees.
"""

import argparse
import math
import sys
import warnings

import numpy as np

import tendonrod as tr
from tendonrod.solver import pack_scene

ROD = dict(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9)


def scenes():
    L = ROD["length"]
    k = tr.Rod(**ROD, kirchhoff=True)
    c = tr.Rod(**ROD)
    three = [tr.Tendon(offset=0.01, angle=2 * math.pi * i / 3, EA=2e4) for i in range(3)]
    return [
        tr.Scene(
            tr.Robot(k, [tr.Tendon(offset=0.01)]),
            displacement=[0.005],
            loads=[tr.PointLoad(s=L, force=(-0.2, 0, 0))],
        ),
        tr.Scene(
            tr.Robot(c, [tr.Tendon.converging(offset=0.01, length=L)]),
            tension=[1.0],
            loads=[tr.DistributedLoad(force=(0, 0, -0.3))],
        ),
        tr.Scene(
            tr.Robot(c, three),
            displacement=[0.004, 0.0, None],
            tension=[None, None, 0.3],
            loads=[
                tr.PointLoad(s=L, force=(0.05, 0.1, 0), moment=(0, 0, 0.001)),
                tr.PointLoad(s=0.12, force=(0, -0.05, 0)),
            ],
        ),
        tr.Scene(
            tr.Robot(k, [tr.Tendon(offset=0.008, end=0.1), tr.Tendon(offset=0.008, angle=math.pi)]),
            displacement=[0.004, -0.002],
            loads=[tr.PointLoad(s=L, force=(0.3, 0, 0))],
        ),
        tr.Scene(tr.Robot(k, [])),
        # channel friction: a load that reverses the curvature (the steps split at the
        # kink), and a frictional tendon anchored mid-length beside a frictionless one
        tr.Scene(
            tr.Robot(k, [tr.Tendon(offset=0.01, EA=3e3, friction=0.4)]),
            displacement=[0.008],
            sliding="out",
            loads=[tr.PointLoad(s=L, force=(-0.3, 0, -0.1))],
        ),
        tr.Scene(
            tr.Robot(
                c,
                [
                    tr.Tendon(offset=0.01, friction=0.3, end=0.12),
                    tr.Tendon(offset=0.01, angle=2.0, EA=2e4),
                ],
            ),
            tension=[1.0, None],
            displacement=[None, 0.002],
            loads=[tr.PointLoad(s=L, force=(0.02, -0.05, 0))],
        ),
    ]


def ufunc_loop(n):
    a = tr.analytic
    s = np.linspace(0.0, 0.2, 7)
    out = np.empty(7)
    args = (0.3, 0.12, 0.2, 4e-3, -0.02, 0.01, 5e4)
    for _ in range(n):
        a.tension(*args)
        a.angle(s, *args)
        a.deflection(s, *args, out=out, where=s > 0.05)
        a.equivalent_stiffness(5e4, np.array([2e5, np.inf]))
        a.pattern_factor(np.arange(1, 6))
        a.actuation_tension_for_angle(0.5, 0.2, 4e-3, -0.02, 0.01)
        a.actuation_tension_for_deflection(0.03, 0.2, 4e-3, -0.02, 0.01)
        with np.errstate(invalid="ignore"):
            assert np.isnan(a.deflection(-1.0, *args))
        try:
            a.angle("x", *args)
        except TypeError:
            pass
    a.planar_shape(s, *args)


def solve_loop(n):
    sc = scenes()
    warnings.simplefilter("ignore", tr.ConvergenceWarning)
    prev = [None] * len(sc)
    for it in range(n):
        i = it % len(sc)
        sol = tr.solve(sc[i], guess=prev[i])
        assert sol.success, sol.message
        prev[i] = sol if it % 3 else None
        if it % 7 == 0:
            tr.solve(sc[i], options=tr.Options(tip_only=True))
            tr.solve(
                sc[i],
                options=tr.Options(
                    nodes=np.array([0.0, 0.05, 0.2]), integrator=("rk4", "rk8", "adaptive")[it % 3]
                ),
            )
            sol.at(0.07)
            # the stability verdict (hyper-dual element Hessians, block LDL^T, bordered
            # tendons, the discrete equilibrium where the margin is small)
            assert sol.stable is not None or sol.stability_reason
            if sc[i].robot.n_tendons:
                tr.compliance(sc[i])
            if any(t.friction for t in sc[i].robot.tendons):
                tr.slip(sol)  # the recording pass's rest lengths, a reference solve
        if it % 11 == 0:
            # failures: an iteration cap, an impossible displacement, strict=True
            bad = tr.Scene(sc[0].robot, displacement=[0.5])
            r = tr.solve(bad, options=tr.Options(max_nfev=50))
            assert not r.success and r.message
            try:
                tr.solve(sc[2], options=tr.Options(max_iter=1, continuation=False), strict=True)
            except tr.ConvergenceError:
                pass


def batch_loop(n):
    """tr.solve_batch on 2 threads, with hopeless points among good ones."""
    sc = scenes()[0]
    q = np.array([[0.002], [0.5], [0.004], [0.006]])
    for _ in range(n):
        r = tr.solve_batch(sc, displacement=q, threads=2, chunksize=2)
        assert r.status[0] >= 0 and r.status[1] < 0
        try:
            tr.solve_batch(sc, displacement=np.array([[np.nan]]))
        except ValueError:
            pass


def problem_loop(n):
    """Problem paths, the confirmation, the budget and a cancelled solve."""
    import pickle
    import threading

    sc = scenes()
    rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    fs = rod.bending_stiffness / 0.1**2
    plain = tr.Robot(rod, [])
    for it in range(n):
        prob = tr.Problem(sc[2])
        assert prob.solve().success
        for f in (0.05, 0.07):
            moved = tr.Scene(
                sc[2].robot,
                displacement=[0.004, 0.0, None],
                tension=[None, None, 0.3],
                loads=[
                    tr.PointLoad(s=0.2, force=(f, 0.1, 0), moment=(0, 0, 0.001)),
                    tr.PointLoad(s=0.12, force=(0, -0.05, 0)),
                ],
            )
            assert prob.solve(moved).success
        prob.solve(guess="cold")
        prob.compliance()
        pickle.loads(pickle.dumps(prob))
        try:
            prob.solve(sc[0])
        except ValueError:
            pass
        # confirmed off the load path (second formulation: tests/test_pipeline.py's
        # reproducer; a pure tensile load now converges directly), the automatic multiple
        # shooting itself, and the budget running out
        conf = tr.Scene(plain, loads=[tr.PointLoad(s=0.1, force=(fs, 0, 196 * fs))])
        segs = tr.Options(tip_only=True, shooting_segments=4)
        assert tr.solve(conf, options=segs).status == tr._core.STATUS_CONFIRMED
        off = tr.Scene(plain, loads=[tr.PointLoad(s=0.1, force=(0, 0, 400 * fs))])
        assert tr.solve(off).formulation.shooting_auto
        hopeless = tr.Scene(plain, loads=[tr.PointLoad(s=0.1, force=(1e6, 0, 0))])
        assert (
            tr.solve(hopeless, options=tr.Options(max_work=2e4)).status == tr._core.STATUS_EBUDGET
        )
        # the stable branch: a buckled column (direct answer unstable, the load path and a
        # symmetry-breaking imperfection), a warm ramp across the bifurcation keeping and
        # renewing verdicts, an unstable planar scene that fails honestly, and the verdict
        # record handed from a Solution to a warm solve
        wire = tr.Rod(0.25, 1.2e-3, 60e9, 23e9, kirchhoff=True)
        pe = math.pi**2 * wire.bending_stiffness / (4 * 0.25**2)

        def column(f):
            return tr.Scene(tr.Robot(wire, []), loads=[tr.PointLoad(s=0.25, force=(0, 0, -f * pe))])

        assert tr.solve(column(1.5)).stable is True
        ramp = tr.Problem(column(0.8))
        for f in (0.8, 0.9, 1.1, 1.2):
            assert ramp.solve(column(f)).stable is not False
        # tendons locked at their taut/slack switch hold the column past its Euler load
        # (every face of the switch tendons' cones tested: tr_switch.c)
        locked = tr.Robot(
            wire, [tr.Tendon(offset=0.01, angle=k * math.pi / 2, EA=3e3) for k in range(4)]
        )
        held = tr.Scene(
            locked, displacement=[0.0] * 4, loads=[tr.PointLoad(s=0.25, force=(0, 0, -1.5 * pe))]
        )
        assert tr.solve(held).stable is True
        fig11a = tr.Scene(
            tr.Robot(rod, [tr.Tendon(offset=0.01)]),
            displacement=[0.01 * math.pi / 2],
            loads=[tr.PointLoad(s=0.1, force=(-4.0, 0, 0))],
        )
        assert tr.solve(fig11a).status == tr._core.STATUS_UNSTABLE
        first = tr.solve(sc[2])
        assert tr.solve(sc[2], guess=first).success
        if it == 0:
            # a solve on a thread stopped by its Cancel token
            from tendonrod._interrupt import cancel_scope

            token = tr._core.Cancel()
            slow = tr.Options(max_work=1e15, max_nfev=10**9, max_continuation=10**6, steps=500)
            caught = []

            def run():
                with cancel_scope(token):
                    try:
                        tr.solve(hopeless, options=slow)
                    except KeyboardInterrupt:
                        caught.append(1)

            t = threading.Thread(target=run)
            t.start()
            token.set()
            t.join()


def raw_error_loop(n):
    rod, tend, loads, dist = pack_scene(scenes()[2])
    bad_calls = [
        ((rod[:5], tend, loads, dist), {}),
        ((rod, tend[:, :7], loads, dist), {}),
        ((rod, tend, loads[:, :6], dist), {}),
        ((rod, tend, loads, dist[:2]), {}),
        ((rod.astype(complex), tend, loads, dist), {}),
        (("rod", tend, loads, dist), {}),
        ((rod, None, loads, dist), {}),
        ((rod, tend, loads, dist), {"steps": -1}),
        ((rod, tend, loads, dist), {"integrator": "nope"}),
        ((rod, tend, loads, dist), {"guess": np.zeros(3)}),
        ((rod, tend, loads, dist), {"nodes": np.array([0.3, 0.1])}),
        ((rod, tend, loads, dist), {"bogus": 1}),
    ]
    rod_nan = rod.copy()
    rod_nan[1] = np.nan
    bad_calls.append(((rod_nan, tend, loads, dist), {}))
    for _ in range(n):
        for args, kw in bad_calls:
            try:
                r = tr._core.solve(*args, **kw)
                assert not r["success"], (args, kw)
            except (ValueError, TypeError):
                pass


def actuate_loop(n):
    """tr.actuate (its run in C, tr_actuate.c): the least change of three tendons, a square
    target (inside the shooting system first), a tip pose by least squares, tension
    controls with a slack tendon, an unreachable target; the glue's error paths and the
    QP's own."""
    rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    EI, r = rod.bending_stiffness, 0.01
    tendons = [
        tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=150.0 * EI / r**2) for i in range(3)
    ]
    robot = tr.Robot(rod, tendons)
    sc = tr.Scene(
        robot, displacement=[0.0, 0.0, 0.0], loads=[tr.PointLoad(s=0.1, force=(0.0, 0.5, 0.0))]
    )
    ten = tr.Scene(robot, tension=[2.0, 0.0, 1.0])
    for it in range(n):
        sol = tr.actuate(sc, tip_direction=(1.0, 0.0, 1.0 + 0.1 * it))
        assert sol.success, sol.message
        sq = tr.actuate(sc, tendons=(0, 1), tip_direction=(0.3, 0.1 * it, 1.0))
        assert sq.actuation.kind == "square", sq.actuation
        pose = (sol.tip_position, sol.tip_rotation)
        ls = tr.actuate(sc, tip_pose=pose, max_iter=5)
        assert ls.actuation.kind == "least-squares", ls.actuation
        tt = tr.actuate(ten, tendons=(0, 1), tip_direction=(0.5, 0.2, 1.0))
        assert tt.actuation.controls.shape == (2,), tt.actuation
        far = tr.actuate(sc, tendons=(0,), tip_position=(0.5, 0.5, 0.5), max_iter=3)
        assert not far.success, far.actuation
        prob = tr.Problem(sc)
        prob.solve()
        for bad in ({"tendons": [7.0]}, {"goal": 9}, {"c0": [0.0, 0.0]}):
            kw = dict(
                kind=1,
                tendons=[0.0, 1.0, 2.0],
                c0=[0.0] * 3,
                scale=[r] * 3,
                values=[0.0] * 3,
                floor=[-np.inf] * 3,
                tau_scale=1.0,
                k=1.0,
                tol=1e-10,
                max_iter=5,
                tip_row=1,
                goal=2,
                length=0.1,
                direction=[0.0, 0.0, 1.0],
                basis=[[1.0, 0, 0], [0, 1.0, 0]],
            )
            kw.update(bad)
            try:
                prob._c.actuate(**kw)
            except ValueError:
                pass
        try:
            tr._core.qp(
                np.zeros((2, 2)), np.ones(2), np.zeros((0, 2)), np.zeros((0, 2)), [], [0, 0]
            )
        except ArithmeticError:
            pass
        try:
            tr._core.qp(np.eye(2), np.ones(3), np.zeros((0, 2)), np.zeros((0, 2)), [], [0, 0])
        except ValueError:
            pass


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--fast", action="store_true", help="small counts (CI)")
    ap.add_argument("--solves", type=int, default=None)
    ap.add_argument("--ufuncs", type=int, default=None)
    a = ap.parse_args(argv)
    n_solve = a.solves if a.solves is not None else (30 if a.fast else 150)
    n_uf = a.ufuncs if a.ufuncs is not None else (50 if a.fast else 300)
    ufunc_loop(n_uf)
    solve_loop(n_solve)
    raw_error_loop(max(2, n_solve // 10))
    batch_loop(max(2, n_solve // 10))
    problem_loop(max(2, n_solve // 15))
    actuate_loop(max(2, n_solve // 15))
    print(
        f"valgrind_loop: {n_uf} ufunc rounds, {n_solve} solves, "
        f"{max(2, n_solve // 10)} rounds of raw error paths: done"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
