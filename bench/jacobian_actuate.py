"""Benchmark: the cost of ``Problem.jacobian`` in warm solves and of ``tr.actuate`` in cold
solves, on the paper's Fig. 11c scene as ``bench/solve.py`` builds it (L = 0.1 m,
d = 1.04 mm, three tendons at 10 mm, the first retracted to a 90 deg tip angle, the
actuators locked, 0.5 N out-of-plane tip load; spatial, 9 shooting unknowns).

Units of cost (measured in every round, and every ratio taken within its round, since
these machines drift by tens of percent; medians over rounds; default ``tr.Options()``):
  * cold solve: ``tr.solve(scene)``;
  * warm solve: ``Problem.solve(scene_i)`` along ``bench/solve.py``'s sweep (loads 1 %
    apart), per solve.
``Problem.jacobian`` is timed at the Problem's solved state (no solve) in four variants:
forward differences over the unknowns (the default) with and without the compliance block
(without it: what ``tr.actuate`` uses), and central differences with and without it.  ``tr.actuate`` is timed from
the scene on targets that are reachable by construction: the tip state of a forward solve
at controls moved by a random step (seeded) of up to 2 mm per tendon:
  * ``tip_position`` with the three tendons (square: 3 controls, 3 components);
  * ``tip_direction`` with the three tendons (least change: 3 controls, 2 components);
  * ``tip_direction`` with tendons 0 and 1 (square: 2 controls, 2 components), by both
    routes (``method="auto"``, the augmented system first, and ``"linearisation"``).
Each row also checks the answer: a cold forward ``tr.solve`` of the returned controls
reaches the target (tip position error / L, tip direction error [rad]).
With ``--instructions`` every kind is also counted by callgrind (valgrind): the
instructions of an ``actuate`` over the targets of the kind (mean per target), over those
of a cold solve: the same ratio in work, free of the timing noise of these machines (but
blind to the lower instruction throughput of Python against the numerical core).
Not a test: it prints a table and writes bench/results/jacobian_actuate.csv and .md.

    .venv/bin/python bench/jacobian_actuate.py [--rounds 7] [--targets 8] [--instructions]
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np

import tendonrod as tr

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from solve import median_time, scenes, sweep_of  # noqa: E402  (bench/solve.py: the scene, timing)

OUT = os.path.join(HERE, "results")
SCENE = "fig11c 3 tendons, out-of-plane load"
GOAL_JACOBIAN_WARM = 2.0  # the goal: tr.jacobian within 2 warm solves
GOAL_ACTUATE_COLD = 5.0  # the goal: tr.actuate within 5 cold solves


def warm_solve(sw) -> float:
    """Per-solve time [s] of a warm Problem along the sweep sw."""
    prob = tr.Problem(sw[0])
    prob.solve()
    t0 = time.perf_counter()
    for s in sw[1:]:
        prob.solve(s)
    return (time.perf_counter() - t0) / (len(sw) - 1)


JACOBIANS = {
    "forward (default), with load": dict(),
    "forward, no load": dict(load=False),
    "central, with load": dict(method="central"),
    "central, no load": dict(load=False, method="central"),
}


LIN = {"method": "linearisation"}


def targets(scene, n: int):
    """(kind, tendons, target dict) reachable by construction (seeded)."""
    rng = np.random.default_rng(15)
    q0 = np.array(scene.displacement)
    out = []
    for _ in range(n):
        q = q0 + rng.uniform(-2e-3, 2e-3, size=3)
        goal = tr.solve(dataclasses.replace(scene, displacement=list(q)), strict=True)
        out.append(("position, 3 tendons", None, {"tip_position": tuple(goal.tip_position)}))
        d = tuple(goal.tip_rotation[:, 2])
        out.append(("direction, 3 tendons", None, {"tip_direction": d}))
        # two tendons, the third locked at the scene's value: the target from a forward
        # solve that moved only those two
        q2 = np.r_[q[:2], q0[2]]
        goal2 = tr.solve(dataclasses.replace(scene, displacement=list(q2)), strict=True)
        d2 = {"tip_direction": tuple(goal2.tip_rotation[:, 2])}
        out.append(("direction, tendons 0 1", (0, 1), d2))
        # the same square targets by steps on the linearisation only: the two routes compared
        out.append(("direction, tendons 0 1, linearisation only", (0, 1), {**d2, **LIN}))
    return out


def reproduce(scene, sol, target) -> float:
    """The target error of a cold forward solve with the controls found."""
    fwd = tr.solve(dataclasses.replace(scene, displacement=list(sol.displacement)))
    target = {k: v for k, v in target.items() if k != "method"}
    if "tip_position" in target:
        return float(
            np.max(np.abs(fwd.tip_position - target["tip_position"])) / scene.robot.rod.length
        )
    t = np.asarray(target["tip_direction"]) / np.linalg.norm(target["tip_direction"])
    z = fwd.tip_rotation[:, 2]
    return float(np.arctan2(np.linalg.norm(np.cross(z, t)), z @ t))


def actuate_quiet(scene, tendons, target):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        return tr.actuate(scene, tendons=tendons, **target)


_COUNTED = """
import sys, warnings
sys.path.insert(0, {here!r})
import tendonrod as tr
from jacobian_actuate import SCENE, actuate_quiet, scenes, targets
scene = scenes()[SCENE][0]
tg = [t for t in targets(scene, {n}) if t[0] == {kind!r}]
def once():
    if tg:
        for _, tendons, target in tg:
            actuate_quiet(scene, tendons, target)
    else:
        for _ in range(10):
            tr.solve(scene)
once()  # imports, caches, compiled problems
for _ in range({reps}):
    once()
"""


def _instructions(kind: str, n: int, reps: int) -> int:
    """Instructions (callgrind) of the script above: the targets of ``kind`` (a cold solve
    ten times for kind "cold") once, then ``reps`` more times."""
    body = _COUNTED.format(here=HERE, n=n, kind=kind, reps=reps)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    with tempfile.TemporaryDirectory() as tmp:
        script, out = os.path.join(tmp, "s.py"), os.path.join(tmp, "cg.out")
        with open(script, "w") as fh:
            fh.write(body)
        run = subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", sys.executable, script],
            env=env,
            capture_output=True,
            text=True,
            check=True,
        )
    return int(re.search(r"Collected : (\d+)", run.stderr).group(1))


def instruction_ratios(kinds, n: int) -> dict:
    """{kind: instructions of one actuate (mean over the kind's targets) / those of one
    cold solve}, each the difference of a run with one more pass over the targets and a
    run without (start-up, imports and first calls excluded)."""
    cold = (_instructions("cold", n, 1) - _instructions("cold", n, 0)) / 10
    out = {}
    for kind in kinds:
        per = (_instructions(kind, n, 1) - _instructions(kind, n, 0)) / n
        out[kind] = per / cold
        print(f"instructions: {kind:<44s} {per / 1e6:7.2f} M  = {per / cold:5.2f} cold solves")
    return out


def measure(scene, rounds: int, n: int):
    """Per round (these machines drift by tens of percent): the solve units, then every
    measurement in them; the medians over rounds of the times and of the ratios."""
    sw = sweep_of(scene)
    prob = tr.Problem(scene)
    prob.solve()
    tg = targets(scene, n)
    per = {"cold": [], "warm": []}
    jac = {k: ([], []) for k in JACOBIANS}
    act = [([], []) for _ in tg]
    for _ in range(rounds):
        cold = median_time(lambda: tr.solve(scene), 5)
        warm = statistics.median(warm_solve(sw) for _ in range(3))
        per["cold"].append(cold)
        per["warm"].append(warm)
        for name, kw in JACOBIANS.items():
            t = median_time(lambda kw=kw: prob.jacobian(**kw), 5)
            jac[name][0].append(t)
            jac[name][1].append(t / warm)
        for i, (_, tendons, target) in enumerate(tg):
            t = median_time(lambda: actuate_quiet(scene, tendons, target), 1)
            act[i][0].append(t)
            act[i][1].append(t / cold)
    med = statistics.median
    rows = []
    for (kind, tendons, target), (ts, us) in zip(tg, act):
        sol = actuate_quiet(scene, tendons, target)
        a = sol.actuation
        rows.append(
            dict(
                kind=kind,
                success=bool(sol.success),
                actuate_ms=1e3 * med(ts),
                cold_units=med(us),
                route=a.route,
                iterations=a.iterations,
                solves=a.solves,
                jacobians=a.jacobians,
                distance=a.distance,
                reproduced=reproduce(scene, sol, target) if sol.success else float("nan"),
            )
        )
    jt = {k: (med(v[0]), med(v[1])) for k, v in jac.items()}
    return med(per["cold"]), med(per["warm"]), jt, rows


EXAMPLE = os.path.join(os.path.dirname(HERE), "examples", "actuate_under_load.toml")


def example(rounds: int):
    """(ms, cold solves of its own scene, route): ``tr.actuate`` on the scene file
    examples/actuate_under_load.toml (Figs. 17-18 robot, 0.3 N tip load, 45 deg), medians
    over rounds, each ratio within its round."""
    from tendonrod.scenefile import load_scene

    spec = load_scene(EXAMPLE)
    scene, target = spec.scene, dict(spec.target)
    times, units = [], []
    for _ in range(rounds):
        cold = median_time(lambda: tr.solve(scene), 7)
        t = median_time(lambda: tr.actuate(scene, **target), 7)
        times.append(t)
        units.append(t / cold)
    route = tr.actuate(scene, **target).actuation.route
    return 1e3 * statistics.median(times), statistics.median(units), route


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--targets", type=int, default=8, help="targets per kind")
    ap.add_argument(
        "--instructions", action="store_true", help="also count instructions (callgrind)"
    )
    args = ap.parse_args(argv)
    scene = scenes()[SCENE][0]
    cold, warm, jac, rows = measure(scene, args.rounds, args.targets)
    kinds = list(dict.fromkeys(r["kind"] for r in rows))
    work = instruction_ratios(kinds, args.targets) if args.instructions else {}
    ex_ms, ex_units, ex_route = example(args.rounds)

    lines = [
        f"# `Problem.jacobian` and `tr.actuate` on the Fig. 11c scene ({platform.machine()}, "
        f"Python {platform.python_version()})",
        "",
        "Produced by `python bench/jacobian_actuate.py "
        f"--rounds {args.rounds} --targets {args.targets}"
        f"{' --instructions' if work else ''}` (medians over rounds of the "
        "times and of the ratios, each ratio within its round; default options).",
        "",
        f"Solve units: cold `tr.solve` {1e6 * cold:.0f} us, warm `Problem.solve` "
        f"{1e6 * warm:.0f} us.",
        "",
        "| Problem.jacobian | us | warm solves | goal <= 2 |",
        "|---|---:|---:|:---:|",
    ]
    print(f"cold solve {1e6 * cold:.0f} us, warm Problem solve {1e6 * warm:.0f} us")
    for name, (t, units) in jac.items():
        ok = "yes" if units <= GOAL_JACOBIAN_WARM else "no"
        lines.append(f"| {name} | {1e6 * t:.0f} | {units:.2f} | {ok} |")
        print(f"Problem.jacobian {name:<20s} {1e6 * t:7.0f} us  {units:5.2f} warm solves")
    lines += [
        "",
        "| tr.actuate target | reached | median ms | median cold solves (max) | goal <= 5 | "
        "solves / linearisations (median) | augmented route | forward-solve error (max) | "
        "work in cold solves (instructions, mean) |",
        "|---|---:|---:|---:|:---:|---:|---:|---:|---:|",
    ]
    for k in kinds:
        rs = [r for r in rows if r["kind"] == k]
        ok = [r for r in rs if r["success"]]
        units = [r["cold_units"] for r in rs]
        med_units = statistics.median(units)
        err = max((r["reproduced"] for r in ok), default=float("nan"))
        line = (
            f"| {k} | {len(ok)}/{len(rs)} | {statistics.median(r['actuate_ms'] for r in rs):.1f} "
            f"| {med_units:.1f} ({max(units):.1f}) | "
            f"{'yes' if med_units <= GOAL_ACTUATE_COLD else 'no'} | "
            f"{statistics.median(r['solves'] for r in rs):.0f} / "
            f"{statistics.median(r['jacobians'] for r in rs):.0f} | "
            f"{sum(r['route'] == 'augmented' and r['success'] for r in rs)}/{len(rs)} | {err:.1e} | "
            + (f"{work[k]:.2f} |" if k in work else "- |")
        )
        lines.append(line)
        print(line)
    line = (
        f"The scene file `examples/actuate_under_load.toml` (Figs. 17-18 robot, 0.3 N tip "
        f"load, 45 deg; route {ex_route}): {ex_ms:.2f} ms, {ex_units:.1f} cold solves of "
        "its own scene (the first solve, the augmented solve, a forward solve of the "
        "controls found and the judged one)."
    )
    lines += ["", line]
    print(line)
    k_unknowns = tr.Problem(scene).formulation.n_unknowns
    its = {k: [r["iterations"] for r in rows if r["kind"] == k] for k in kinds}
    missed = {k: sum(not r["success"] for r in rows if r["kind"] == k) for k in kinds}
    lines += [
        "",
        "What the numbers say. `tr.actuate` takes two routes: a square target whose "
        "controls are displacements is first solved inside the shooting system (its "
        "residual in place of the actuated tendons' length constraints: one Newton solve, "
        "the `route` 'augmented'); the rest, and what that solve leaves, by Newton / SQP "
        "steps on `Problem.jacobian` around warm solves.",
        "",
        "- `Problem.jacobian` costs k + 1 shooting evaluations with forward differences "
        f"over the k = {k_unknowns} unknowns (the default, step 5e-8 in the scaled units) and "
        "2 k + 1 with central ones, where a warm 1 % step takes a handful; loads at the tip "
        "and displacement controls enter the shooting map in closed form and cost nothing. "
        "Forward differences give derivatives within ~2e-8 of the central ones relative to "
        "each column on this scene, ~1e-7 at worst on the test scenes (a Cosserat rod's EA "
        "and GA, rounding-bound), but ~1e-6 where a fast direction of the unknowns barely "
        "moves the pose (the common tension level of a stiff taut tendon pair on a straight "
        "robot, tests/test_jacobian.py::test_at_switch_one_sided_taut_side, which asks for "
        "central ones); central ones (truncation ~1e-11) are the numbers of "
        "`tr.compliance`, which keeps them.",
        "- `tr.actuate` runs in the core from its first solve on (`csrc/tr_actuate.c`, "
        "`csrc/tr_act_run.c`, one call with the GIL released): a warm solve and a forward "
        "linearisation of the tip by the controls per iteration, the step a small QP "
        "(`csrc/tr_qp.c`); in the least change, after a step whose target residual fell by "
        "100x or more, a chord step on the same linearisation replaces the next iteration. "
        "Each warm solve starts from the last success with the shooting Jacobian of the last "
        "linearisation (not after one at a taut/slack switch, whose one-sided Jacobian may "
        "be the wrong side's), a tendon "
        "released or drawn in from the same equilibrium with its slack changed, a return to "
        "controls solved before from that solution; near the target each takes one Newton "
        "step past convergence (a control change under the solver's tol otherwise left the "
        "state where it was, and one square target stalled at 1.03e-10). Iterations per "
        "target (median, max): "
        + "; ".join(
            f"{k} {statistics.median(its[k]):.0f}, {max(its[k])}"
            + (f" ({missed[k]} of {len(its[k])} stop short of the target)" if missed[k] else "")
            for k in kinds
        )
        + ". The least change stops at a stationarity of 1e-6 in the scaled controls (the "
        "forward-difference linearisation is good to ~1e-7, so 1e-7 chased its noise). The "
        "least-change targets whose solution holds a tendon at its tension floor take 3-4 "
        "iterations; those that keep all three taut (co-contraction, 13-100 N) 5-7, the "
        "tangential convergence of the quasi-Newton Hessian being linear at first.",
        "- Where the time goes (the 'direction, 3 tendons' targets, timers around the two "
        "calls into the core, mean): the first solve 0.56 cold solves (no stability verdict), "
        "the core's run 2.7 (iterate solves, linearisations, the final judged solve ~0.5), "
        "Python 0.75 (the checks, the target's frame, the result; its plausibility check "
        "~0.3, with a recording pass where a state finding needs one). The run was Python "
        "until this version (the least change 5.4-6.5 cold solves in time, 4.4 in "
        "instructions): moved to C with the same rules, it takes the same iterations, "
        "solves and linearisations per target but for round-off-driven differences of one "
        "or two (the 32 targets: 191 / 284 / 221 against 192 / 285 / 222 on the positions, "
        "37 / 67 / 39 against 37 / 65 / 38 on the least change), and its ~2 cold solves of "
        "Python (~0.5 ms an iteration of numpy calls on 3-vectors) are gone.",
        "- Found on the way, in the core (all solves): a tendon's tension/slack unknown was "
        "differenced forward whatever the side of its switch; across the kink that is "
        "neither side's derivative, and iterate solves that land a tendon at its tension "
        "floor took 10-22 Newton iterations and up to 18 fresh Jacobians (64-206 "
        "evaluations) for an unknown move of 1e-7..1e-3; now 1-17 (the large first steps "
        "of the co-contracted targets still take 64-93). Golden outputs changed at "
        "round-off; the stress report's outcomes are unchanged.",
        "- Position targets with three tendons are badly conditioned (the third singular "
        "value of the tip's derivative by the controls is ~0.4 % of the first: "
        "co-contraction moves the tip little, and does so nonlinearly as the tension "
        "stiffens the robot): the trust region shrinks to steps of ~1e-3 and the steps creep; "
        "1 of 8 targets stops short of 1e-10 L (3.3e-7 after the 50 iterations). A second "
        "one stalled at 1.4e-2 with 8 refused steps: two tendons held at their switch, "
        "which the step slackened through the third while their taut-side derivatives "
        "predicted otherwise; such a tendon is now linearised on its slack side and the "
        "step retaken, which reaches it (1e-13, tests/test_actuate.py), at the price of "
        "more linearisations where tendons cross their switch back and forth (the kind's "
        "work 15.0 -> 18.0 cold solves, its median time 15-19 -> 22).",
        "- Tried and dropped (in instructions, over the 8 targets of each kind): the "
        "linearisation's Jacobian also after a switch (3 % less work on the least change, 13 % "
        "more on the positions, 8 % more on the square targets by steps); the chord step in "
        "the square and least-squares steps too (3 % more on the positions); a secant (good "
        "Broyden) update of the control Jacobian (no fewer "
        "evaluations, fewer position targets reached); the iterate solves started from the "
        "linearised state (no cheaper); a tension floor a hair above its value, to keep the "
        "iterates off the switch (slower); a 1-d secant of the reduced Hessian in place of "
        "the damped BFGS update (more iterations on the taut targets); the least-norm normal "
        "step by `lstsq` in place of its QP (more instructions than the QP in C); the least "
        "change inside the shooting system (n - m coupling rows holding the controls' change "
        "in the row space of the last linearisation: saved nothing over the steps on a "
        "pretensioned four-tendon robot); a tip pose (6 components) inside the shooting "
        "system (stagnated from 70 % of the way).",
    ]
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "jacobian_actuate.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
        f.write(f"# cold_us={1e6 * cold:.1f} warm_us={1e6 * warm:.1f}\n")
        for name, (t, units) in jac.items():
            f.write(f"# jacobian {name}: {1e6 * t:.1f} us, {units:.3f} warm solves\n")
    with open(os.path.join(OUT, "jacobian_actuate.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
