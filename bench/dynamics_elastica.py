"""Benchmark: a large-amplitude transient of a plain Cosserat rod, ``tr.simulate``
against PyElastica (Gazzola et al. 2018), each refined until it converges.

The scene: a 1 m rod of 10 mm diameter (rho = 1000 kg/m^3, E = 0.5 GPa, G = E/3 as
PyElastica's default Poisson ratio 0.5), clamped at the origin along world +z, gravity
-9.81 m/s^2 along world -x (a horizontal cantilever, q L^3 / EI = 3.1), held at rest by
a tip force of twice its weight along +x (tip 0.70 m above the base line), the force
released over --tau = 0.2 s by a half cosine (--tau 0: at once, at t = 0): the rod swings
down through its sag and back, 1.55 m of tip travel, over 1.5 s (f1 = 0.99 Hz).
Undamped in both codes (PyElastica's dampers are not Kelvin-Voigt).  Matched:
GA = (27/28) G A (PyElastica's shear factor alpha_c; tendonrod is given that GA),
EA = E A, EI = E I, GJ = 2 G I, rho A, rotary inertia rho (I, I, 2I).  PyElastica starts
from tendonrod's static state (positions at its nodes, rotations at its element centres
from ``Solution.at``; the clamp holds the first element in that initial frame).

PyElastica runs in its own virtual environment (``--elastica-python``, default
/work/venv-elastica/bin/python), as a subprocess of this same file in worker mode
(``--worker``: no tendonrod import), writing the tip every 2.5 ms and its loop's thread
CPU and wall time to an .npz.  tendonrod runs here (BDF2; single shooting fails below 0.005 s on this scene, and
tr.simulate then redoes the run on two segments, which pass down to 0.0025 s: --sweep,
docs/validation/dynamics_elastica.md).

Not a test: prints tables, writes bench/results/dynamics_elastica.csv and
docs/images/dynamics_elastica.png (--tau 0: dynamics_elastica_sudden.csv and .png in
bench/results; --static: the static sag, dynamics_elastica_static.csv; --sweep:
tendonrod alone over dt, alpha and shooting segments against the PyElastica runs of
--cache, dynamics_elastica[_sudden]_sweep.csv; --quick: dynamics_elastica_quick.*, not
kept).

    .venv/bin/python bench/dynamics_elastica.py [--quick] [--tau 0] [--static | --sweep]
        [--cache FILE]
        [--elastica-python PATH]
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import pickle
import subprocess
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "results")
FIG = os.path.join(HERE, "..", "docs", "images", "dynamics_elastica.png")

L, RADIUS, RHO, E = 1.0, 0.005, 1000.0, 5e8
G = E / 3.0
ALPHA_C = 27.0 / 28.0  # PyElastica's shear factor (Kaneko 1975 for Poisson ratio 0.5)
GRAVITY = np.array([-9.81, 0.0, 0.0])
T_END = 1.5
SAMPLE = 0.0025  # PyElastica's recording interval [s]
COMMON = 0.03  # the comparison's time grid [s]: a multiple of every dt used
HOLD = 2.0  # the held tip force, in weights of the rod
WEIGHT = RHO * math.pi * RADIUS**2 * 9.81 * L  # [N]


def held_force(t, tau):
    """The tip force along world +x [N] at t [s]: HOLD weights, released over tau [s]
    by a half cosine (tau = 0: at once, at t = 0)."""
    if t >= tau:
        return 0.0
    return HOLD * WEIGHT * 0.5 * (1.0 + math.cos(math.pi * t / tau))


# --------------------------------------------------------------------------- PyElastica
def _elastica_sim(n, pos=None, dirs=None, tau=0.0, relax=0.0, dt=None):
    import elastica as ea

    class Sim(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping):
        pass

    class Release(ea.NoForces):
        """The held tip force, world frame, on the last node."""

        def apply_forces(self, system, time=0.0):
            system.external_forces[0, -1] += held_force(float(time), tau)

    sim = Sim()
    rod = ea.CosseratRod.straight_rod(
        n,
        np.zeros(3),
        np.array([0.0, 0.0, 1.0]),
        np.array([1.0, 0.0, 0.0]),
        L,
        RADIUS,
        RHO,
        youngs_modulus=E,
        shear_modulus=G,
    )
    if pos is not None:  # before the clamp reads its position and frame
        rod.position_collection[:] = pos
        rod.director_collection[:] = dirs
    sim.append(rod)
    sim.constrain(rod).using(
        ea.OneEndFixedBC, constrained_position_idx=(0,), constrained_director_idx=(0,)
    )
    sim.add_forcing_to(rod).using(ea.GravityForces, acc_gravity=GRAVITY.copy())
    if tau > 0:
        sim.add_forcing_to(rod).using(Release)
    if relax > 0:  # the static check: velocities decay as exp(-relax t)
        sim.dampen(rod).using(
            ea.AnalyticalLinearDamper, uniform_damping_constant=relax, time_step=dt
        )
    sim.finalize()  # the clamp: node 0 at the origin, element 0 in its initial frame
    return sim, rod


def worker(args) -> None:
    """PyElastica's run (in its own venv): tip every SAMPLE s to args.out (.npz)."""
    import elastica as ea

    n, dt = args.n, args.dt
    stepper = ea.PositionVerlet()
    warm, _ = _elastica_sim(5)  # numba's compilation outside the timing
    for _ in range(3):
        stepper.step(warm, 0.0, 1e-6)
    if args.relax > 0:  # from straight, under gravity alone, damped to rest
        sim, rod = _elastica_sim(n, relax=args.relax, dt=dt)
    else:
        init = np.load(args.init)
        sim, rod = _elastica_sim(n, init[f"pos{n}"], init[f"dirs{n}"], args.tau)
    per = int(round(SAMPLE / dt))
    nsteps = int(round(args.T / dt))
    tips = [rod.position_collection[:, -1].copy()]
    t = np.float64(0.0)
    c0, w0 = time.thread_time(), time.perf_counter()
    for i in range(1, nsteps + 1):
        t = stepper.step(sim, t, dt)
        if i % per == 0:
            tips.append(rod.position_collection[:, -1].copy())
    cpu, wall = time.thread_time() - c0, time.perf_counter() - w0
    tip = np.array(tips)
    vmax = float(np.abs(rod.velocity_collection).max())
    np.savez(
        args.out, t=SAMPLE * np.arange(len(tip)), tip=tip, cpu=cpu, wall=wall, n=n, dt=dt, vmax=vmax
    )


# --------------------------------------------------------------------------- tendonrod
def scenes():
    import tendonrod as tr

    area = math.pi * RADIUS**2
    rod = tr.Rod(L, 2 * RADIUS, E, G, density=RHO, GA=ALPHA_C * G * area)
    free = tr.Scene(tr.Robot(rod, []), gravity=tuple(GRAVITY))
    held = tr.Scene(
        tr.Robot(rod, []), gravity=tuple(GRAVITY), loads=[tr.PointLoad(L, (HOLD * WEIGHT, 0, 0))]
    )
    return free, held


def elastica_initial(held, ns, path) -> None:
    """tendonrod's static held state at PyElastica's nodes and element centres."""
    import tendonrod as tr

    sol = tr.solve(held, options=tr.Options(integrator="rk4", steps=400, force_spatial=True))
    out = {}
    for n in ns:
        ds = L / n
        out[f"pos{n}"] = sol.at(ds * np.arange(n + 1)).position.T.copy()
        rot = sol.at(ds * (np.arange(n) + 0.5)).rotation  # (n, 3, 3) body to world
        out[f"dirs{n}"] = np.transpose(rot, (2, 1, 0)).copy()  # Q[:, :, k] = R_k^T
    np.savez(path, **out)


def run_elastica(py, init, n, dt, T, tau, relax=0.0):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "e.npz")
        cmd = [py, os.path.abspath(__file__), "--worker", "--init", str(init), "--out", out]
        cmd += ["--n", str(n), "--dt", repr(dt), "--T", repr(T), "--tau", repr(tau)]
        cmd += ["--relax", repr(relax)]
        subprocess.run(cmd, check=True)
        with np.load(out) as f:
            return {k: f[k] for k in f}


def run_tendonrod(free, held, dt, steps, T, tau):
    import tendonrod as tr

    def loads(t):
        return [tr.PointLoad(L, (held_force(t, tau), 0.0, 0.0))]

    c0, w0 = time.thread_time(), time.perf_counter()
    start = tr.solve(held, options=tr.simulation_options(steps))
    opts = {"steps": steps, "alpha": 0.0, "max_iter": 30}
    if tau > 0:  # the held scene, its tip force released by loads(t)
        traj = tr.simulate(held, T, dt, loads=loads, initial=start, options=opts)
    else:
        traj = tr.simulate(free, T, dt, initial=start, options=opts)
    cpu, wall = time.thread_time() - c0, time.perf_counter() - w0
    return {
        "t": traj.t,
        "tip": traj.tip_position,
        "cpu": cpu,
        "wall": wall,
        "ok": traj.success,
        "msg": traj.message,
        "iters": int(traj.iterations.sum()),
    }


def on_grid(run, grid):
    """The tip at the times ``grid`` (each a sample of the run)."""
    idx = np.rint(grid / (run["t"][1] - run["t"][0])).astype(int)
    assert np.allclose(run["t"][idx], grid, atol=1e-9)
    return run["tip"][idx]


def maxdiff(a, b, grid):
    return float(np.linalg.norm(on_grid(a, grid) - on_grid(b, grid), axis=1).max()) / L


def elastica_dt(n):
    """Half of Position Verlet's stability limit 2 / omega_max, omega_max^2 from the
    bending of one element (8 E / (rho ds^2)) and its thickness shear (4 alpha_c G /
    (rho r^2)); a divisor of SAMPLE."""
    ds = L / n
    omega = math.sqrt(8 * E / (RHO * ds * ds) + 4 * ALPHA_C * G / (RHO * RADIUS**2))
    return SAMPLE / math.ceil(SAMPLE * omega)


def elastica_runs(args, held, ns, T):
    """PyElastica's runs by n (its dt at half its stability limit), and at the coarsest n
    with dt / 2 and dt / 4; keyed (n, dt divisor)."""
    with tempfile.TemporaryDirectory() as tmp:
        init = os.path.join(tmp, "init.npz")
        elastica_initial(held, ns, init)
        pe = {}
        for n in ns:
            pe[(n, 1)] = run_elastica(args.elastica_python, init, n, elastica_dt(n), T, args.tau)
        for k in (2, 4):
            pe[(ns[0], k)] = run_elastica(
                args.elastica_python, init, ns[0], elastica_dt(ns[0]) / k, T, args.tau
            )
    return pe


# tendonrod's runs: BDF2 (dt [s], RK4 steps); its reference from the last two dt at 20 steps
TR_QUICK = ((0.015, 20), (0.01, 20), (0.0075, 20))
TR_FULL = ((0.015, 20), (0.01, 20), (0.0075, 20), (0.005, 20), (0.0075, 40), (0.005, 40))


def bench(args) -> None:
    quick = args.quick
    T = 0.3 if quick else T_END
    grid = COMMON * np.arange(int(round(T / COMMON)) + 1)
    ns = (25, 50) if quick else (25, 50, 100, 200)
    free, held = scenes()
    load = os.getloadavg()
    print(f"load average at start: {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    if args.cache and os.path.exists(args.cache):
        with open(args.cache, "rb") as fh:
            pe = pickle.load(fh)
    else:
        pe = elastica_runs(args, held, ns, T)
        if args.cache:
            with open(args.cache, "wb") as fh:
                pickle.dump(pe, fh)
    rows = [
        {"code": "pyelastica", "n": n, "dt": float(r["dt"]), "run": r} for (n, _k), r in pe.items()
    ]
    trs = {}
    for dt, steps in TR_QUICK if quick else TR_FULL:
        r = trs[(dt, steps)] = run_tendonrod(free, held, dt, steps, T, args.tau)
        if not r["ok"]:
            print(f"tendonrod dt={dt} steps={steps} left out: {r['msg']}")
            del trs[(dt, steps)]
            continue
        rows.append({"code": "tendonrod", "n": steps, "dt": dt, "run": r})
    # the references, each code's extrapolation: PyElastica's tip as x + a/n + b/n^2 from
    # its three finest n (two in --quick), tendonrod's BDF2 as x + c dt^2 from its two
    # finest dt; each with the spread of a second extrapolation as its uncertainty
    x = {n: on_grid(pe[(n, 1)], grid) for n in ns}
    e2 = 2 * x[ns[-1]] - x[ns[-2]]
    if quick:
        e_ref, e_alt = e2, e2
    else:
        e_ref = (8 * x[ns[-1]] - 6 * x[ns[-2]] + x[ns[-3]]) / 3
        e_alt = e2
    tdts = sorted({dt for dt, st in trs if st == 20})
    f, c, c2 = (on_grid(trs[(dt, 20)], grid) for dt in tdts[:3])
    q = tdts[1] / tdts[0]
    t_ref = f + (f - c) / (q * q - 1)
    q2 = tdts[2] / tdts[0]
    t_alt = f + (f - c2) / (q2 * q2 - 1)
    e_ref, t_ref = {"t": grid, "tip": e_ref}, {"t": grid, "tip": t_ref}
    spread = {
        "pyelastica": maxdiff(e_ref, {"t": grid, "tip": e_alt}, grid),
        "tendonrod": maxdiff(t_ref, {"t": grid, "tip": t_alt}, grid),
    }
    for row in rows:
        row["err_e"] = maxdiff(row["run"], e_ref, grid)
        row["err_t"] = maxdiff(row["run"], t_ref, grid)
    refdiff = maxdiff(e_ref, t_ref, grid)
    report(rows, refdiff, spread, grid, e_ref, t_ref, pe, ns, load, quick, args.tau, tdts)


def report(rows, refdiff, spread, grid, e_ref, t_ref, pe, ns, load, quick, tau, tdts) -> None:
    print(
        f"\nreferences: PyElastica {'2 x(n) - x(n/2)' if quick else 'x + a/n + b/n^2'} "
        f"from n = {ns[-3:]} (spread against "
        f"2 x({ns[-1]}) - x({ns[-2]}): {spread['pyelastica']:.2e} L); tendonrod BDF2 "
        f"x + c dt^2 from dt = {tdts[0]}, {tdts[1]} s (spread against dt = {tdts[0]}, "
        f"{tdts[2]} s: {spread['tendonrod']:.2e} L)"
    )
    print(f"max |tip_PyElastica_ref - tip_tendonrod_ref| / L over the run: {refdiff:.2e}")
    hdr = (
        f"{'code':11s} {'n/steps':>7s} {'dt [s]':>10s} {'CPU [s]':>8s} {'wall [s]':>8s} "
        f"{'err vs PyE ref':>14s} {'err vs tr ref':>13s} {'Newton':>7s}"
    )
    print(hdr)
    for r in rows:
        x = r["run"]
        print(
            f"{r['code']:11s} {r['n']:7d} {r['dt']:10.3e} {float(x['cpu']):8.3f} "
            f"{float(x['wall']):8.3f} {r['err_e']:14.2e} {r['err_t']:13.2e} {x.get('iters', '')!s:>7s}"
        )
    # PyElastica's order in n: successive differences at the finest dt
    d = [maxdiff(pe[(a, 1)], pe[(b, 1)], grid) for a, b in zip(ns[:-1], ns[1:])]
    print(
        "PyElastica |x(n) - x(2n)| / L:",
        ", ".join(f"{v:.2e}" for v in d),
        " ratios:",
        ", ".join(f"{a / b:.2f}" for a, b in zip(d[:-1], d[1:])),
    )
    d = [maxdiff(pe[(ns[0], 1)], pe[(ns[0], k)], grid) for k in (2, 4)]
    print(f"PyElastica n={ns[0]}: |x(dt) - x(dt/2)|, |x(dt) - x(dt/4)| / L: {d[0]:.1e}, {d[1]:.1e}")
    tr = {(r["dt"], r["n"]): r["run"] for r in rows if r["code"] == "tendonrod"}
    for (dt, st), run in tr.items():
        if st != 20 and (dt, 20) in tr:
            g = maxdiff(run, tr[(dt, 20)], grid)
            print(f"tendonrod dt={dt}: |x(20 RK4) - x({st} RK4)| / L: {g:.1e}")
    name = "dynamics_elastica_quick" if quick else "dynamics_elastica"
    if tau == 0 and not quick:
        name += "_sudden"
    with open(os.path.join(OUT, name + ".csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "code",
                "n_or_steps",
                "dt_s",
                "cpu_s",
                "wall_s",
                "err_vs_pyelastica_ref_L",
                "err_vs_tendonrod_ref_L",
                "load1",
            ]
        )
        for r in rows:
            x = r["run"]
            w.writerow(
                [
                    r["code"],
                    r["n"],
                    f"{r['dt']:.6e}",
                    f"{float(x['cpu']):.4f}",
                    f"{float(x['wall']):.4f}",
                    f"{r['err_e']:.3e}",
                    f"{r['err_t']:.3e}",
                    f"{load[0]:.2f}",
                ]
            )
        w.writerow(["refs_difference", "", "", "", "", f"{refdiff:.3e}", "", f"{load[0]:.2f}"])
        w.writerow(
            [
                "refs_spread",
                "",
                "",
                "",
                "",
                f"{spread['pyelastica']:.3e}",
                f"{spread['tendonrod']:.3e}",
                "",
            ]
        )
    figure(rows, e_ref, t_ref, grid, ns, name)


def figure(rows, e_ref, t_ref, grid, ns, name) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    pe = [r for r in rows if r["code"] == "pyelastica"]
    te = [r for r in rows if r["code"] == "tendonrod"]
    pbest = next(r for r in pe if r["n"] == ns[-1])["run"]
    tbest = te[-1]
    for k, lab in ((0, "x (up)"), (2, "z (along the base)")):
        ax[0].plot(
            pbest["t"],
            pbest["tip"][:, k],
            "-",
            lw=3,
            alpha=0.45,
            label=f"PyElastica n={ns[-1]}: {lab}",
        )
        ax[0].plot(
            tbest["run"]["t"],
            tbest["run"]["tip"][:, k],
            "k--",
            lw=1,
            label=f"tendonrod dt={tbest['dt']} s: {lab}",
        )
    ax[0].set_xlabel("t [s]")
    ax[0].set_ylabel("tip position, world frame [m]")
    ax[0].set_ylim(-1.0, 1.5)
    ax[0].legend(fontsize=7, ncol=2, loc="upper center")
    ax[0].set_title("the tip, released from a held deflection")
    e_tr = np.linalg.norm(on_grid(t_ref, grid) - on_grid(e_ref, grid), axis=1) / L
    ax[1].semilogy(
        grid[1:],
        np.maximum(e_tr[1:], 1e-9),
        "k-",
        lw=2.5,
        label="tendonrod's extrapolation (dt) vs PyElastica's (n)",
    )
    dt0 = {r["n"]: max(q["dt"] for q in pe if q["n"] == r["n"]) for r in pe}
    for r in [r for r in pe if r["dt"] == dt0[r["n"]]] + te:
        x = r["run"]
        e = np.linalg.norm(on_grid(x, grid) - on_grid(e_ref, grid), axis=1) / L
        if r["code"] == "pyelastica":
            ax[1].semilogy(
                grid[1:],
                np.maximum(e[1:], 1e-9),
                "-",
                lw=1,
                label=f"PyElastica n={r['n']}, dt={r['dt']:.2e} s",
            )
        elif r["n"] == te[0]["n"]:
            ax[1].semilogy(
                grid[1:],
                np.maximum(e[1:], 1e-9),
                "--",
                lw=1,
                label=f"tendonrod dt={r['dt']} s, {r['n']} RK4",
            )
    ax[1].set_xlabel("t [s]")
    ax[1].set_ylabel("|tip - PyElastica's extrapolated tip| / L")
    ax[1].legend(fontsize=6)
    ax[1].set_title("difference from PyElastica's converged tip")
    series = (
        (
            "PyElastica, n refined (dt at its limit / 2)",
            [r for r in pe if r["dt"] == dt0[r["n"]]],
            "o-",
        ),
        (f"PyElastica n={ns[0]}, dt/2, dt/4", [r for r in pe if r["dt"] < dt0[r["n"]]], "o"),
        (
            f"tendonrod, dt refined ({te[0]['n']} RK4)",
            [r for r in te if r["n"] == te[0]["n"]],
            "s-",
        ),
        ("tendonrod, 40 RK4", [r for r in te if r["n"] != te[0]["n"]], "s"),
    )
    for lab, sel, mk in series:
        if not sel:
            continue
        cpu = [float(r["run"]["cpu"]) for r in sel]
        line = ax[2].loglog(
            cpu, [r["err_e"] for r in sel], mk, label=lab + ": vs PyElastica's ref."
        )
        ax[2].loglog(
            cpu,
            [r["err_t"] for r in sel],
            mk[0],
            ls=":" if "-" in mk else "",
            mfc="none",
            color=line[0].get_color(),
            label=lab + ": vs tendonrod's ref.",
        )
    ax[2].set_xlabel("thread CPU time of the run [s]")
    ax[2].set_ylabel("max |tip error| / L over the run")
    ax[2].legend(fontsize=6)
    ax[2].set_title("error against run time")
    fig.tight_layout()
    path = FIG if name == "dynamics_elastica" else os.path.join(OUT, name + ".png")
    fig.savefig(path, dpi=110)
    print("wrote", path)


def static_check(args) -> None:
    """The cantilever's static sag under its weight: PyElastica from straight, damped to
    rest (4 s, velocities decaying as exp(-12 t)), against tendonrod's static solve; no
    constructed state, PyElastica's own clamp."""
    import tendonrod as tr

    free, _ = scenes()
    tip = tr.solve(free, options=tr.Options(integrator="rk4", steps=400, force_spatial=True))
    tip = tip.tip_position
    ns = (25, 50) if args.quick else (25, 50, 100)
    load = os.getloadavg()
    print(f"load average at start: {load[0]:.2f}; tendonrod's tip {tip} m")
    x = {}
    rows = []
    for n in ns:
        r = run_elastica(args.elastica_python, "", n, elastica_dt(n), 4.0, 0.0, relax=12.0)
        x[n] = r["tip"][-1]
        err = float(np.linalg.norm(x[n] - tip)) / L
        rows.append(
            [
                n,
                f"{float(r['dt']):.6e}",
                f"{float(r['cpu']):.2f}",
                f"{err:.3e}",
                f"{float(r['vmax']):.1e}",
                *(f"{v:.8f}" for v in x[n]),
            ]
        )
        print(
            f"PyElastica n={n}: tip {x[n]}, |tip - tendonrod's| / L = {err:.2e}, "
            f"max |v| at the end {float(r['vmax']):.1e} m/s, CPU {float(r['cpu']):.1f} s"
        )
    ext = 2 * x[ns[-1]] - x[ns[-2]]
    err = float(np.linalg.norm(ext - tip)) / L
    print(f"PyElastica 2 x({ns[-1]}) - x({ns[-2]}): {ext}, |. - tendonrod's| / L = {err:.2e}")
    rows.append([f"2x{ns[-1]}-x{ns[-2]}", "", "", f"{err:.3e}", "", *(f"{v:.8f}" for v in ext)])
    rows.append(["tendonrod", "", "", "", "", *(f"{v:.8f}" for v in tip)])
    name = "dynamics_elastica_static" + ("_quick" if args.quick else "")
    with open(os.path.join(OUT, name + ".csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["n", "dt_s", "cpu_s", "err_vs_tendonrod_L", "vmax_end", "x", "y", "z"])
        w.writerows(rows)


# the dt sweep (--sweep): which steps tendonrod takes on this scene, by alpha, with the
# shooting segments tr.simulate chooses (None) or forced
SWEEP = (
    (0.0, (0.006, 0.005, 0.0045, 0.004, 0.003, 0.0025), None),
    (-0.5, (0.015, 0.01, 0.0075, 0.006, 0.005, 0.004, 0.003, 0.0025), None),
    (0.0, (0.006, 0.005, 0.004, 0.003, 0.0025), 2),
    (0.0, (0.006, 0.005, 0.004, 0.003, 0.0025), 4),
    (-0.5, (0.01, 0.0075, 0.005), 2),
    (-0.5, (0.01, 0.0075, 0.005), 4),
)


def sweep(args) -> None:
    """tendonrod alone at the dt of SWEEP (20 RK4 steps, max_iter 30, shooting segments
    chosen by tr.simulate), each against PyElastica's extrapolated tip from the runs in
    --cache (required: the default run's pickle); writes <name>_sweep.csv."""
    import re

    import tendonrod as tr
    from tendonrod import _core
    from tendonrod.compiled import _compile

    if not (args.cache and os.path.exists(args.cache)):
        raise SystemExit("--sweep needs --cache FILE holding PyElastica's runs")
    with open(args.cache, "rb") as fh:
        pe = pickle.load(fh)
    ns = sorted({n for n, _k in pe})[-3:]
    grid = COMMON * np.arange(int(round(T_END / COMMON)) + 1)
    x = [on_grid(pe[(n, 1)], grid) for n in ns]
    ref = {"t": grid, "tip": (8 * x[2] - 6 * x[1] + x[0]) / 3}
    free, held = scenes()
    load = os.getloadavg()
    print(f"load average at start: {load[0]:.2f}; PyElastica's reference from n = {ns}")
    rows = []
    kept = {}
    for alpha, dts, nseg in SWEEP:
        for dt in dts:
            c0, w0 = time.thread_time(), time.perf_counter()
            start = tr.solve(held, options=tr.simulation_options(20))
            opts = {"steps": 20, "alpha": alpha, "max_iter": 30, "segments": nseg}
            if args.tau > 0:
                ld = lambda t: [tr.PointLoad(L, (held_force(t, args.tau), 0.0, 0.0))]  # noqa: E731
                traj = tr.simulate(held, T_END, dt, loads=ld, initial=start, options=opts)
            else:
                traj = tr.simulate(free, T_END, dt, initial=start, options=opts)
            cpu, wall = time.thread_time() - c0, time.perf_counter() - w0
            m = re.search(r"(\d+) (?:shooting )?segment", traj.message)
            seg = str(nseg) if nseg else m.group(1) if m else ""
            if not seg:
                prob = _compile(held, tr.simulation_options(20))
                seg = str(_core.dyn_segments(prob, held.robot.rod.mass_per_length, dt, alpha)[0])
            run = {"t": traj.t, "tip": traj.tip_position}
            # the comparison's times that are samples of this dt (every 0.06 s for
            # dt = 0.004 s, every 0.09 s for 0.0045 s)
            g = grid[np.abs(grid / dt - np.rint(grid / dt)) < 1e-6]
            err = maxdiff(run, ref, g) if traj.success else float("nan")
            if traj.success and alpha == 0.0 and nseg == 2:
                kept[dt] = run
            its = int(traj.iterations.sum())
            steps = len(traj.t) - 1
            print(
                f"alpha={alpha:5.2f} dt={dt:7.4f} segments={seg:>2s} ok={traj.success!s:5s} "
                f"err={err:9.2e} L CPU={cpu:7.3f} s wall={wall:7.3f} s "
                f"Newton/step={its / max(steps, 1):5.1f}  {'' if traj.success else traj.message}"
            )
            rows.append(
                [
                    alpha,
                    dt,
                    seg,
                    int(traj.success),
                    f"{err:.3e}",
                    f"{cpu:.4f}",
                    f"{wall:.4f}",
                    f"{its / max(steps, 1):.2f}",
                    f"{float(traj.t[-1]):.4f}",
                    "" if traj.success else traj.message,
                    f"{load[0]:.2f}",
                ]
            )
    # BDF2's extrapolation x + c dt^2 from its two finest dt (2 segments), against
    # PyElastica's; its spread against the extrapolation from the finest and the third
    fine = sorted(d for d in kept if abs(COMMON / d - round(COMMON / d)) < 1e-9)[:3]
    if len(fine) == 3:
        f, c, c2 = (on_grid(kept[d], grid) for d in fine)
        ext = {"t": grid, "tip": f + (f - c) / ((fine[1] / fine[0]) ** 2 - 1)}
        alt = {"t": grid, "tip": f + (f - c2) / ((fine[2] / fine[0]) ** 2 - 1)}
        d_ref, d_alt = maxdiff(ext, ref, grid), maxdiff(ext, alt, grid)
        print(
            f"BDF2 (2 segments) extrapolated from dt = {fine[0]}, {fine[1]} s: "
            f"{d_ref:.2e} L from PyElastica's extrapolation (its spread against dt = "
            f"{fine[0]}, {fine[2]} s: {d_alt:.2e} L)"
        )
        rows.append(
            [
                "bdf2_extrapolated",
                f"{fine[0]}/{fine[1]}",
                2,
                1,
                f"{d_ref:.3e}",
                "",
                "",
                "",
                "",
                f"spread {d_alt:.3e}",
                f"{load[0]:.2f}",
            ]
        )
    name = "dynamics_elastica" + ("_sudden" if args.tau == 0 else "") + "_sweep"
    with open(os.path.join(OUT, name + ".csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "alpha",
                "dt_s",
                "segments",
                "ok",
                "err_vs_pyelastica_ref_L",
                "cpu_s",
                "wall_s",
                "newton_per_step",
                "t_reached_s",
                "message",
                "load1",
            ]
        )
        w.writerows(rows)
    print("wrote", os.path.join(OUT, name + ".csv"))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smoke run (coarse, 0.3 s)")
    ap.add_argument("--elastica-python", default="/work/venv-elastica/bin/python")
    ap.add_argument("--cache", help="a pickle of the runs: read if it exists, else written")
    ap.add_argument(
        "--static",
        action="store_true",
        help="instead: the static sag under gravity alone, PyElastica damped to rest",
    )
    ap.add_argument(
        "--sweep",
        action="store_true",
        help="instead: tendonrod alone over a range of dt and alpha (needs --cache)",
    )
    ap.add_argument("--relax", type=float, default=0.0, help=argparse.SUPPRESS)
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--init", help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    ap.add_argument("--n", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--dt", type=float, help=argparse.SUPPRESS)
    ap.add_argument("--T", type=float, help=argparse.SUPPRESS)
    ap.add_argument(
        "--tau",
        type=float,
        default=0.2,
        help="the release's duration [s] (half cosine; 0: at once)",
    )
    args = ap.parse_args()
    if args.worker:
        worker(args)
    elif args.static:
        static_check(args)
    elif args.sweep:
        sweep(args)
    else:
        bench(args)


if __name__ == "__main__":
    main()
