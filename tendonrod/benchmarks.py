"""Benchmarks: error against run time (work-precision) and the stress suite.

Command line (routed here by ``python -m tendonrod bench ...``)::

    python -m tendonrod bench work-precision --out DIR [--quick]
    python -m tendonrod bench stress --out DIR [--quick] [--timeout SECONDS] [--only SUBSTRING]

work-precision
    Solves a fixed set of scenes (circle under an end moment, elastica under a tip
    force, a small load on a straight robot, the paper's Fig. 11 a-c, the Fig. 17
    slack scene past its critical load, a three-tendon robot with very stiff
    tendons under an out-of-plane load) with every integrator (rk4 and rk8 over a
    range of step counts, the adaptive integrator over a range of rtol) and every
    Jacobian option, and records the relative tip error against an exact or
    independently converged reference (:mod:`tendonrod.references`), the median
    run time of a cold solve, iterations and evaluations. Writes
    ``DIR/work_precision.csv`` and ``DIR/work_precision.png``; then the choice-of-
    model chart (closed form vs Cosserat for a straight robot under a growing tip
    load, paper Fig. 10): ``DIR/model_choice.csv`` and ``DIR/model_choice.png``.

stress
    Runs every stress case in a child process with a timeout and checks each
    result: a well-posed case must converge to a *verified* answer (finite, global
    force and moment balance, agreement under step refinement and with the
    adaptive integrator, plus a case-specific check where an independent answer
    is known); an ill-posed case must return ``success=False`` with a message.
    Writes ``DIR/stress.csv`` and ``DIR/stress.png``.

Nothing here is timed inside the test suite; the tests import the scene
builders and the verification functions and run small subsets.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import sys
import time
import traceback
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from . import references as refs

# --------------------------------------------------------------------------- robots
#: Paper Section IV-B (Figs. 11-16): Kirchhoff backbone L = 0.1 m, d = 1.04 mm,
#: E = 210 GPa, G = 80 GPa, tendon offset 0.01 m.
FIG11 = dict(L=0.1, d=1.04e-3, E=210e9, G=80e9, r=0.01)
#: Paper Figs. 17-18: L = 0.2 m, d = 0.8 mm, E = 207 GPa, G = 79.6 GPa, offset 0.01 m.
FIG17 = dict(L=0.2, d=0.8e-3, E=207e9, G=79.6e9, r=0.01)


def _tr():
    import tendonrod as tr

    return tr


def rod_of(p, kirchhoff=True, **kw):
    tr = _tr()
    return tr.Rod(p["L"], p["d"], p["E"], p["G"], kirchhoff=kirchhoff, **kw)


def EI_of(p):
    return p["E"] * math.pi * p["d"] ** 4 / 64.0


def three_tendon_actuation(EI, L, r, EA, pretension, theta):
    """Displacements q_i = Delta cos(phi_i) of three equally spaced pretensioned
    parallel tendons (phi = 0, 2pi/3, 4pi/3) that bend a Kirchhoff backbone to tip
    angle ``theta`` toward tendon 0 (exact: the bend is a circle). The tension
    change of tendon i is (EA + tau_p)/L (l_i + q_i - L) (stretch measured from the
    rest length L/(1 + tau_p/EA)); moment balance EI kappa = 1.5 r (EA + tau_p)/L
    (Delta - L kappa r) gives Delta = kappa L r (1 + EI / (1.5 r^2 (EA + tau_p)))."""
    kappa = theta / L
    EAe = EA + pretension
    delta = kappa * L * r * (1.0 + EI / (1.5 * r * r * EAe))
    return [delta * math.cos(2 * math.pi * i / 3) for i in range(3)]


# --------------------------------------------------------------------------- scenes
@dataclass
class WPScene:
    """A work-precision scene: the Scene, how to get its reference tip, and how the
    error is normalised."""

    name: str
    title: str
    scene: object
    reference: Callable[[], np.ndarray]  # -> reference tip position (3,) [m]
    ref_kind: str  # "exact", "closed form", "independent ODE"
    scale: Callable[[np.ndarray], float]  # reference tip -> error normaliser [m]
    components: tuple = (0, 1, 2)  # which tip components enter the error
    slack_models: tuple = ("linear",)


def _tip_scale(ref):
    return float(np.linalg.norm(ref))


def wp_scenes() -> list[WPScene]:
    """The fixed scene set of the work-precision benchmark."""
    tr = _tr()
    out = []
    # 1. circle: a pure end moment, exact for any rod (Cosserat backbone here).
    p = FIG11
    L, EI = p["L"], EI_of(p)
    M = (0.0, math.pi * EI / L, 0.0)  # a half circle
    sc = tr.Scene(tr.Robot(rod_of(p, kirchhoff=False), []), loads=[tr.PointLoad(s=L, moment=M)])
    out.append(
        WPScene(
            "circle",
            "circle: end moment, half turn (exact)",
            sc,
            lambda L=L, EI=EI, M=M: refs.circle_end_moment(L, EI, M)[0][0],
            "exact",
            _tip_scale,
        )
    )
    # 2. elastica: Kirchhoff cantilever, transverse tip force F L^2/EI = 5 (tip angle 70 deg).
    F = 5.0 * EI / L**2
    sc = tr.Scene(
        tr.Robot(rod_of(p, kirchhoff=True), []), loads=[tr.PointLoad(s=L, force=(F, 0.0, 0.0))]
    )

    def ela(L=L, EI=EI, F=F):
        x, z, _ = refs.elastica_tip_force(L, EI, F)
        return np.array([x, 0.0, z])

    out.append(
        WPScene("elastica", "elastica: tip force FL²/EI = 5 (exact)", sc, ela, "exact", _tip_scale)
    )
    # 3. small load on the straight robot (Fig. 17 robot, one inextensible parallel
    #    tendon at q = 0): F L^2/EI = 1e-6, so the closed form's own (nonlinear) error is
    #    O((F L^2/EI)^2) = 1e-12 of the deflection. The error is normalised by the
    #    deflection (the tip moves 1e-7 L), transverse components only.
    p = FIG17
    L, EI, r = p["L"], EI_of(p), p["r"]
    F = 1e-6 * EI / L**2
    sc = tr.Scene(
        tr.Robot(rod_of(p), [tr.Tendon(offset=r)]),
        displacement=[0.0],
        loads=[tr.PointLoad(s=L, force=(-F, 0.0, 0.0))],
    )

    def small(L=L, EI=EI, F=F, r=r):
        d = float(refs.small_load_deflection(L, F, L, L, EI, 0.0, r, np.inf))
        return np.array([-d, 0.0, L])

    out.append(
        WPScene(
            "small_load",
            "small load FL²/EI = 1e-6, straight robot (closed form)",
            sc,
            small,
            "closed form",
            lambda ref: abs(ref[0]),
            components=(0, 1),
        )
    )
    # 4-6. Fig. 11 a-c: actuated by displacement to a 90 deg tip angle.
    p = FIG11
    L, EI, r = p["L"], EI_of(p), p["r"]
    q90 = r * math.pi / 2  # inextensible tendon on a Kirchhoff rod: theta_L = q / r exactly
    one = tr.Robot(rod_of(p), [tr.Tendon(offset=r)])
    sc = tr.Scene(one, displacement=[q90], loads=[tr.PointLoad(s=L, force=(-1.0, 0.0, 0.0))])
    out.append(
        WPScene(
            "fig11a",
            "Fig. 11a: 90° + transverse 1 N",
            sc,
            _ref_from_scene(sc),
            "independent ODE",
            _tip_scale,
        )
    )
    sc = tr.Scene(one, displacement=[q90], loads=[tr.PointLoad(s=L, force=(0.0, 0.0, -1.0))])
    out.append(
        WPScene(
            "fig11b",
            "Fig. 11b: 90° + axial 1 N",
            sc,
            _ref_from_scene(sc),
            "independent ODE",
            _tip_scale,
        )
    )
    out.append(
        _three_tendon_scene(
            "fig11c",
            "Fig. 11c: 3 tendons r²kL/(3EI)=50, out-of-plane 0.5 N",
            p,
            alpha=150.0,
            Fy=0.5,
        )
    )
    # 7. Fig. 17 past the critical load: the tendon is slack, the tip is a free elastica.
    p = FIG17
    L, EI, r = p["L"], EI_of(p), p["r"]
    P = 0.5  # critical load is refs.critical_tip_angle_load(L, EI, pi/2) = 0.358 N
    sc = tr.Scene(
        tr.Robot(rod_of(p), [tr.Tendon(offset=r)]),
        displacement=[r * math.pi / 2],
        loads=[tr.PointLoad(s=L, force=(0.0, 0.0, -P))],
    )

    def slack(L=L, EI=EI, P=P):
        x, z, _ = refs.elastica_compressive(L, EI, P)
        return np.array([x, 0.0, z])

    out.append(
        WPScene(
            "fig17_slack",
            "Fig. 17: 90°, axial 0.5 N > 0.358 N critical (slack, exact)",
            sc,
            slack,
            "exact",
            _tip_scale,
            slack_models=("linear", "squared"),
        )
    )
    # 8. three very stiff tendons (r^2 k L / EI = 1e8), out-of-plane load.
    out.append(
        _three_tendon_scene(
            "stiff3", "3 tendons r²kL/EI = 1e8, out-of-plane 0.5 N", FIG11, alpha=1e8, Fy=0.5
        )
    )
    return out


def _three_tendon_scene(name, title, p, alpha, Fy, theta=math.pi / 2):
    """Three equally spaced pretensioned parallel tendons (r^2 k L / EI = alpha each,
    k = EA/L) on the Kirchhoff backbone ``p``, bent to ``theta`` by balanced
    displacements, out-of-plane tip force ``Fy`` [N]. Pretension 2 EI theta/(3 r L)
    keeps every tendon taut (the tension change at 90 deg is -EI theta/(1.5 r L)/2
    on the two outer tendons)."""
    tr = _tr()
    L, EI, r = p["L"], EI_of(p), p["r"]
    EA = alpha * EI / (r * r)
    tp = 2.0 * EI * theta / (3.0 * r * L)
    tendons = [
        tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA, pretension=tp) for i in range(3)
    ]
    q = three_tendon_actuation(EI, L, r, EA, tp, theta)
    sc = tr.Scene(
        tr.Robot(rod_of(p), tendons),
        displacement=q,
        loads=[tr.PointLoad(s=L, force=(0.0, Fy, 0.0))],
    )
    return WPScene(name, title, sc, _ref_from_scene(sc), "independent ODE", _tip_scale)


def _ref_from_scene(sc):
    def f():
        return refs.from_scene(sc).solve().tip_position

    return f


# --------------------------------------------------------------------------- timing
def _solve_quiet(scene, options, guess=None):
    tr = _tr()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return tr.solve(scene, guess=guess, options=options)


def time_solve(scene, options, repeats, guess=None):
    """(median seconds of ``repeats`` solves, last Solution)."""
    ts = []
    sol = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        sol = _solve_quiet(scene, options, guess)
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts)), sol


def wp_settings(quick: bool):
    """(method label, options kwargs, setting value) for every integrator setting."""
    if quick:
        rk4 = [8, 32, 128]
        rk8 = [2, 4, 8, 16]
        rt = [1e-6, 1e-9, 1e-12]
    else:
        rk4 = [4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 512, 1024]
        rk8 = [1, 2, 3, 4, 5, 6, 8, 10, 12, 16, 24, 32, 48, 64]
        rt = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13]
    out = []
    for n in rk4:
        out.append(("rk4", dict(integrator="rk4", steps=n), n))
    for n in rk8:
        out.append(("rk8", dict(integrator="rk8", steps=n), n))
    for t in rt:
        out.append(("adaptive", dict(integrator="adaptive", rtol=t), t))
    return out


#: Shooting tolerance of the work-precision runs: far below every integrator error
#: shown, so the curves measure the integrators, not the stopping test.
WP_TOL = 1e-13


def jacobian_methods():
    try:
        from .options import _JACOBIANS

        return list(_JACOBIANS)
    except ImportError:  # pragma: no cover
        return ["fd"]


def tip_error(sc: WPScene, tip, ref):
    c = list(sc.components)
    return float(np.linalg.norm(np.asarray(tip)[c] - ref[c]) / sc.scale(ref))


def run_work_precision(
    out: str,
    quick: bool = False,
    repeats: int | None = None,
    log=print,
    scenes: list[str] | None = None,
):
    tr = _tr()
    os.makedirs(out, exist_ok=True)
    repeats = repeats or (3 if quick else 7)
    allsc = wp_scenes()
    if scenes:
        unknown = set(scenes) - {s.name for s in allsc}
        if unknown:
            raise ValueError(
                f"unknown work-precision scene(s) {sorted(unknown)}; known: {[s.name for s in allsc]}"
            )
    scenes = [s for s in allsc if not scenes or s.name in scenes]
    refs_ = load_references(scenes, out, log)
    rows = []
    for sc in scenes:
        ref = refs_[sc.name]
        # cross-check: the core's own adaptive integrator at its tightest setting
        xs = _solve_quiet(
            sc.scene, tr.Options(integrator="adaptive", rtol=1e-13, tol=WP_TOL, tip_only=True)
        )
        xerr = tip_error(sc, xs.tip_position, ref) if xs.success else math.nan
        log(
            f"[{sc.name}] reference ({sc.ref_kind}) tip {np.array2string(ref, precision=9)}; "
            f"core adaptive 1e-13 differs by {xerr:.2e} (success={xs.success})"
        )
        for jm in jacobian_methods():
            for slack_model in sc.slack_models:
                for method, kw, setting in wp_settings(quick):
                    # the adaptive integrator's residual is only smooth in the unknowns to about
                    # its rtol (its step sequence changes with them), so its shooting tolerance
                    # follows rtol; fixed-step residuals are smooth to round-off
                    tol = (
                        WP_TOL if method != "adaptive" else max(WP_TOL, min(1e-10, 1e-3 * setting))
                    )
                    try:
                        opts = tr.Options(
                            tol=tol,
                            jacobian_method=jm,
                            slack_model=slack_model,
                            tip_only=True,
                            **kw,
                        )
                        secs, sol = time_solve(sc.scene, opts, repeats)
                    except Exception as exc:  # noqa: BLE001 - record, never abort the table
                        rows.append(
                            dict(
                                scene=sc.name,
                                method=method,
                                jacobian=jm,
                                slack_model=slack_model,
                                setting=setting,
                                tol=tol,
                                error=math.nan,
                                seconds=math.nan,
                                nit=-1,
                                nfev=-1,
                                success=False,
                                steps_used=-1,
                                residual=math.nan,
                                reference=sc.ref_kind,
                                ref_check=xerr,
                                message=f"{type(exc).__name__}: {exc}",
                            )
                        )
                        continue
                    err = (
                        tip_error(sc, sol.tip_position, ref)
                        if np.all(np.isfinite(sol.tip_position))
                        else math.nan
                    )
                    rows.append(
                        dict(
                            scene=sc.name,
                            method=method,
                            jacobian=jm,
                            slack_model=slack_model,
                            setting=setting,
                            tol=tol,
                            error=err,
                            seconds=secs,
                            nit=sol.nit,
                            nfev=sol.nfev,
                            success=bool(sol.success),
                            steps_used=sol.formulation.steps,
                            residual=sol.residual_norm,
                            reference=sc.ref_kind,
                            ref_check=xerr,
                            message=sol.message,
                        )
                    )
                    log(
                        f"  {sc.name:12s} {method:8s} {jm:11s} {slack_model:7s} {setting:>8g}: err {err:9.2e} "
                        f"t {secs * 1e3:8.3f} ms nit {sol.nit:3d} nfev {sol.nfev:5d} ok={sol.success}"
                    )
        # what a user gets: default options
        secs, sol = time_solve(sc.scene, tr.Options(), repeats)
        err = tip_error(sc, sol.tip_position, ref)
        rows.append(
            dict(
                scene=sc.name,
                method="default",
                jacobian=tr.Options().jacobian_method,
                slack_model=tr.Options().slack_model,
                setting=0,
                tol=tr.Options().tol,
                error=err,
                seconds=secs,
                nit=sol.nit,
                nfev=sol.nfev,
                success=bool(sol.success),
                steps_used=sol.formulation.steps,
                residual=sol.residual_norm,
                reference=sc.ref_kind,
                ref_check=xerr,
                message=sol.message,
            )
        )
        log(f"  {sc.name:12s} default Options(): err {err:.2e} t {secs * 1e3:.3f} ms")
    cols = [
        "scene",
        "method",
        "jacobian",
        "slack_model",
        "setting",
        "tol",
        "error",
        "seconds",
        "nit",
        "nfev",
        "success",
        "steps_used",
        "residual",
        "reference",
        "ref_check",
        "message",
    ]
    _write_csv(os.path.join(out, "work_precision.csv"), rows, cols)
    plot_work_precision(rows, scenes, os.path.join(out, "work_precision.png"))
    summary = summarize_work_precision(rows)
    with open(os.path.join(out, "work_precision_summary.md"), "w") as fh:
        fh.write(summary)
    log(summary)
    return rows


def load_references(scenes, out, log=print):
    """Reference tips {name: (3,)} for ``scenes``, cached in ``out/references.json``
    (keyed by the scene's repr, so a changed scene is recomputed). The independent
    ODE references take 10-70 s each in pure Python."""
    cache_path = os.path.join(out, "references.json")
    cache = {}
    # the committed cache (bench/results/references.json of a source checkout) first,
    # then the output directory's own; keys include the scene's repr, so an entry is
    # only used for exactly the scene it was computed for
    committed = os.path.join(
        os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
        "bench",
        "results",
        "references.json",
    )
    for path in (committed, cache_path):
        if os.path.exists(path):
            with open(path) as fh:
                cache.update(json.load(fh))
    res = {}
    for sc in scenes:
        key = sc.name + ":" + repr(sc.scene)
        if key not in cache:
            t0 = time.perf_counter()
            ref = np.asarray(sc.reference(), dtype=float)
            cache[key] = {
                "tip": ref.tolist(),
                "kind": sc.ref_kind,
                "seconds": time.perf_counter() - t0,
            }
            log(
                f"[{sc.name}] reference ({sc.ref_kind}) computed in {time.perf_counter() - t0:.1f} s"
            )
            with open(cache_path, "w") as fh:
                json.dump(cache, fh, indent=1)
        res[sc.name] = np.array(cache[key]["tip"], dtype=float)
    return res


def _write_csv(path, rows, cols):
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def read_csv(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


_STYLE = {
    "rk4": ("tab:blue", "o"),
    "rk8": ("tab:red", "s"),
    "adaptive": ("tab:green", "^"),
    "default": ("k", "*"),
}


def plot_work_precision(rows, scenes, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(scenes)
    ncol = 4
    nrow = (n + ncol - 1) // ncol
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 3.6 * nrow), squeeze=False)
    floor = 1e-16
    for ax, sc in zip(axes.ravel(), scenes):
        sub = [r for r in rows if r["scene"] == sc.name]
        keys = []
        for r in sub:
            k = (r["method"], r["jacobian"], r["slack_model"])
            if k not in keys:
                keys.append(k)
        for k in keys:
            pts = [
                r
                for r in sub
                if (r["method"], r["jacobian"], r["slack_model"]) == k
                and r["success"]
                and np.isfinite(r["error"])
                and np.isfinite(r["seconds"])
            ]
            fails = [
                r
                for r in sub
                if (r["method"], r["jacobian"], r["slack_model"]) == k
                and not r["success"]
                and np.isfinite(r["seconds"])
            ]
            color, marker = _STYLE.get(k[0], ("gray", "x"))
            ls = {"fd": "-", "newton": "--", "hybrid": "-."}.get(k[1], (0, (1, 3)))
            if k[2] != "linear":
                ls = ":"
            label = (
                k[0]
                if k[0] == "default"
                else f"{k[0]} ({k[1]}{', ' + k[2] if k[2] != 'linear' else ''})"
            )
            if pts:
                # in the order of increasing work (steps up, rtol down), so timing noise
                # shows as a wiggle, not as a reordering of the line
                pts.sort(
                    key=lambda r: float(r["setting"]) * (-1 if r["method"] == "adaptive" else 1)
                )
                ax.loglog(
                    [r["seconds"] * 1e3 for r in pts],
                    [max(r["error"], floor) for r in pts],
                    ls=ls if k[0] != "default" else "none",
                    marker=marker,
                    color=color,
                    ms=4,
                    label=label,
                    alpha=0.85,
                )
            if fails:
                ax.loglog(
                    [r["seconds"] * 1e3 for r in fails],
                    [max(r["error"], floor) if np.isfinite(r["error"]) else 1.0 for r in fails],
                    ls="none",
                    marker="x",
                    color=color,
                    ms=6,
                )
        ax.set_ylim(3e-17, 3.0)
        ax.set_title(sc.title, fontsize=8.5)
        ax.set_xlabel("median run time per cold solve [ms]", fontsize=8)
        ax.set_ylabel("relative tip error", fontsize=8)
        ax.grid(True, which="major", alpha=0.3)
        ax.tick_params(labelsize=7)
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    h, lab = axes.ravel()[0].get_legend_handles_labels()
    for ax in axes.ravel()[1:n]:
        hh, ll = ax.get_legend_handles_labels()
        for a, b in zip(hh, ll):
            if b not in lab:
                h.append(a)
                lab.append(b)
    fig.legend(h, lab, loc="lower center", ncol=min(6, len(lab)), fontsize=8)
    fig.suptitle(
        "tendonrod work-precision: relative tip error vs run time (x: solve reported failure)",
        fontsize=11,
    )
    fig.tight_layout(rect=(0, 0.11, 1, 0.96))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def replot_work_precision(out):
    """Redraw ``out/work_precision.png`` from ``out/work_precision.csv``."""
    rows = []
    for r in read_csv(os.path.join(out, "work_precision.csv")):
        r = dict(r)
        r["success"] = r["success"] == "True"
        for k in ("error", "seconds"):
            r[k] = float(r[k]) if r[k] not in ("", None) else math.nan
        rows.append(r)
    names = []
    for r in rows:
        if r["scene"] not in names:
            names.append(r["scene"])
    scenes = [s for s in wp_scenes() if s.name in names]
    plot_work_precision(rows, scenes, os.path.join(out, "work_precision.png"))


def summarize_work_precision(rows, targets=(1e-4, 1e-6, 1e-8, 1e-10)):
    """Markdown: per scene and accuracy target, the fastest method reaching it."""
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    lines = [
        "| scene | "
        + " | ".join(f"fastest to {t:.0e}" for t in targets)
        + " | default Options() |",
        "|---|" + "---|" * (len(targets) + 1),
    ]
    for s in scenes:
        sub = [r for r in rows if r["scene"] == s and r["success"] and np.isfinite(r["error"])]
        cells = []
        for t in targets:
            ok = [r for r in sub if r["error"] <= t and r["method"] != "default"]
            if not ok:
                cells.append("—")
                continue
            b = min(ok, key=lambda r: r["seconds"])
            cells.append(
                f"{b['method']} {_fmt_setting(b)} ({b['jacobian']}): {b['seconds'] * 1e3:.3g} ms"
            )
        d = [r for r in rows if r["scene"] == s and r["method"] == "default"]
        if d:
            d = d[0]
            cells.append(
                f"err {d['error']:.1e}, {d['seconds'] * 1e3:.3g} ms"
                + ("" if d["success"] else " FAILED")
            )
        else:
            cells.append("")
        lines.append(f"| {s} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _fmt_setting(r):
    if r["method"] == "adaptive":
        return f"rtol={float(r['setting']):.0e}"
    return f"{int(float(r['setting']))} steps"


# --------------------------------------------------------------------------- convergence order
def observed_order(steps, errors, lo=1e-13, hi=1e-3):
    """Least-squares slope of -log(error) against log(steps) on the asymptotic range:
    errors between ``lo`` (above round-off and the reference's own error) and ``hi``
    (below the pre-asymptotic regime). Returns (slope, number of points used)."""
    steps = np.asarray(steps, dtype=float)
    errors = np.asarray(errors, dtype=float)
    m = np.isfinite(errors) & (errors > lo) & (errors < hi)
    if m.sum() < 2:
        return math.nan, int(m.sum())
    slope = -np.polyfit(np.log(steps[m]), np.log(errors[m]), 1)[0]
    return float(slope), int(m.sum())


# --------------------------------------------------------------------------- model choice
def run_model_choice(out: str, quick: bool = False, log=print):
    """Paper Fig. 10: straight robot (Fig. 17 robot, one parallel tendon at q = 0)
    under a growing transverse tip load; error of the closed form (eq. 26 at the
    tip) against the Cosserat solution, beside the run time of each."""
    tr = _tr()
    os.makedirs(out, exist_ok=True)
    p = FIG17
    L, EI, r = p["L"], EI_of(p), p["r"]
    loads = np.logspace(-3, 2, 11 if quick else 26)  # F L^2 / EI
    variants = [("no tendon", None), ("tendon r²kL/EI = 1", 1.0), ("inextensible tendon", math.inf)]
    ref_opts = tr.Options(integrator="rk8", steps=256, tol=1e-11)  # fine enough at F L^2/EI = 100
    deflection = getattr(getattr(tr, "analytic", None), "deflection", None)
    cf_name = (
        "tr.analytic.deflection" if deflection is not None else "references.small_load_deflection"
    )
    if deflection is None:
        deflection = refs.small_load_deflection
    rows = []
    for name, alpha in variants:
        if alpha is None:
            robot = tr.Robot(rod_of(p), [])
            k = 0.0
        else:
            EA = math.inf if math.isinf(alpha) else alpha * EI / r**2
            k = EA / L
            robot = tr.Robot(rod_of(p), [tr.Tendon(offset=r, EA=EA)])
        prev = None
        for fl in loads:
            F = fl * EI / L**2
            disp = None if alpha is None else [0.0]
            sc = tr.Scene(robot, displacement=disp, loads=[tr.PointLoad(s=L, force=(-F, 0.0, 0.0))])
            # closed form: scalar call timing (median of many) and vectorised per point
            reps = 200
            t0 = time.perf_counter()
            for _ in range(reps):
                d_cf = float(deflection(L, F, L, L, EI, 0.0, r, k))
            t_cf = (time.perf_counter() - t0) / reps
            vec = np.full(10000, F)
            t0 = time.perf_counter()
            deflection(L, vec, L, L, EI, 0.0, r, k)
            t_vec = (time.perf_counter() - t0) / vec.size
            t_cold, sol = time_solve(sc, tr.Options(), 3 if quick else 7)
            t_warm = math.nan
            if prev is not None:
                t_warm, _ = time_solve(sc, tr.Options(), 3 if quick else 7, guess=prev)
            # the Cosserat answer of record follows the loading path: warm started from the
            # previous (smaller) load's answer, never from a cold solve, which can land on
            # another, unstable equilibrium at large loads (stress finding S0)
            if prev is None:
                ref = _solve_quiet(sc, ref_opts)
            else:
                # sub-steps of at most 10 % in load: a 58 % step from a warm start already
                # jumps to another branch at F L^2/EI ~ 40-60 (finding S0)
                f_prev = -prev.scene.point_loads[0].force[0]
                nsub = max(1, int(math.ceil(math.log(F / f_prev) / math.log(1.1))))
                ref = prev
                off_path = False
                for Fk in np.geomspace(f_prev, F, nsub + 1)[1:]:
                    sck = tr.Scene(
                        robot, displacement=disp, loads=[tr.PointLoad(s=L, force=(-Fk, 0.0, 0.0))]
                    )
                    last = ref
                    ref = _solve_quiet(sck, ref_opts, guess=ref)
                    if not ref.success:
                        break
                    # a 10 % load step moves the tip by a few % of L at most; more means the
                    # warm-started solve jumped to another equilibrium (finding S7)
                    if np.linalg.norm(ref.tip_position - last.tip_position) > 0.05 * L:
                        off_path = True
                        break
                if off_path:
                    log(
                        f"  {name}: F L^2/EI = {fl:.3g}: warm-started solve left the loading path; dropped"
                    )
                    rows.append(
                        dict(
                            model=name,
                            load=fl,
                            force=F,
                            closed_form=d_cf,
                            cosserat=math.nan,
                            error=math.nan,
                            cosserat_vs_exact=math.nan,
                            seconds_closed_scalar=t_cf,
                            seconds_closed_vector=t_vec,
                            seconds_cosserat_cold=t_cold,
                            seconds_cosserat_warm=math.nan,
                            cosserat_success=False,
                            default_error=math.nan,
                        )
                    )
                    continue
            if ref.success:
                prev = ref
            x = -ref.tip_position[0]
            err = abs(d_cf - x) / abs(x) if ref.success else math.nan
            exact = math.nan
            if alpha is None:  # no tendon: the exact elastica checks the answer of record
                xe, ze, _ = refs.elastica_tip_force(L, EI, F)
                exact = float(np.hypot(ref.tip_position[0] + xe, ref.tip_position[2] - ze) / L)
            rows.append(
                dict(
                    model=name,
                    load=fl,
                    force=F,
                    closed_form=d_cf,
                    cosserat=x,
                    error=err,
                    cosserat_vs_exact=exact,
                    seconds_closed_scalar=t_cf,
                    seconds_closed_vector=t_vec,
                    seconds_cosserat_cold=t_cold,
                    seconds_cosserat_warm=t_warm,
                    cosserat_success=bool(ref.success),
                    default_error=(
                        float(np.linalg.norm(sol.tip_position - ref.tip_position)) / L
                        if sol.success
                        else math.nan
                    ),
                )
            )
            log(
                f"  {name:22s} FL²/EI={fl:8.3g}: closed-form error {err:.2e}; closed {t_cf * 1e6:.2f} µs, "
                f"Cosserat cold {t_cold * 1e3:.3f} ms warm {t_warm * 1e3:.3f} ms"
            )
    cols = [
        "model",
        "load",
        "force",
        "closed_form",
        "cosserat",
        "error",
        "seconds_closed_scalar",
        "seconds_closed_vector",
        "seconds_cosserat_cold",
        "seconds_cosserat_warm",
        "cosserat_success",
        "default_error",
        "cosserat_vs_exact",
    ]
    _write_csv(os.path.join(out, "model_choice.csv"), rows, cols)
    plot_model_choice(rows, os.path.join(out, "model_choice.png"), cf_name)
    return rows


def plot_model_choice(rows, path, cf_name):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    models = []
    for r in rows:
        if r["model"] not in models:
            models.append(r["model"])
    colors = ["tab:gray", "tab:blue", "tab:red"]
    for m, c in zip(models, colors):
        sub = [r for r in rows if r["model"] == m]
        a1.loglog(
            [r["load"] for r in sub],
            [max(r["error"], 1e-17) for r in sub],
            "o-",
            color=c,
            ms=3,
            label=m,
        )
    for lvl, txt in ((0.01, "1 %"), (0.1, "10 %")):
        a1.axhline(lvl, color="k", lw=0.6, ls=":")
        a1.text(1.2e-3, lvl * 1.15, txt, fontsize=8)
    a1.set_xlabel("tip load  F L² / EI")
    a1.set_ylabel("relative error of the closed-form tip deflection")
    a1.set_title("closed form (eq. 26) vs Cosserat, straight robot", fontsize=10)
    a1.legend(fontsize=8)
    a1.grid(True, alpha=0.3)
    sub = [r for r in rows if r["model"] == models[-1]]
    ld = [r["load"] for r in sub]
    a2.loglog(
        ld,
        [r["seconds_closed_scalar"] * 1e6 for r in sub],
        "s-",
        color="tab:green",
        ms=3,
        label="closed form, one scalar call",
    )
    a2.loglog(
        ld,
        [r["seconds_closed_vector"] * 1e6 for r in sub],
        "s--",
        color="tab:green",
        ms=3,
        label="closed form, per point of a 10⁴ array",
    )
    a2.loglog(
        ld,
        [r["seconds_cosserat_cold"] * 1e6 for r in sub],
        "o-",
        color="tab:red",
        ms=3,
        label="Cosserat, cold solve (default Options)",
    )
    warm = [
        (r["load"], r["seconds_cosserat_warm"] * 1e6)
        for r in sub
        if np.isfinite(r["seconds_cosserat_warm"])
    ]
    if warm:
        a2.loglog(*zip(*warm), "o--", color="tab:red", ms=3, label="Cosserat, warm start (sweep)")
    a2.set_xlabel("tip load  F L² / EI")
    a2.set_ylabel("run time [µs]")
    a2.set_title(f"run time (inextensible tendon; {cf_name})", fontsize=10)
    a2.legend(fontsize=8)
    a2.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --------------------------------------------------------------------------- stress
@dataclass
class StressCase:
    """One stress case. ``build()`` -> (Scene, Options). ``well_posed``: must converge
    to a verified answer; otherwise it must fail honestly (success False, a message
    containing one of ``expect_words`` if given). ``check(sol)`` -> (error, ok, note)
    compares with an independent answer where one is known."""

    name: str
    group: str
    build: Callable
    well_posed: bool = True
    expect_words: tuple = ()
    check: Callable | None = None
    quick: bool = False
    ramp: Callable | None = None  # custom runner (load ramps): sol-less, returns dict


def _stress_opts(**kw):
    tr = _tr()
    return tr.Options(**kw)


def _one_tendon_scene(
    p, theta, alpha=math.inf, F=(0.0, 0.0, 0.0), kirchhoff=True, r=None, EI_override=None, slope=0.0
):
    """One parallel tendon at +x on robot ``p`` displaced to bend an (unloaded)
    backbone to ``theta``: q = r theta (1 + 1/alpha) (exact for a Kirchhoff rod),
    with tip force F (world)."""
    tr = _tr()
    L = p["L"]
    r = p["r"] if r is None else r
    EI = EI_of(p)
    EA = math.inf if math.isinf(alpha) else alpha * EI / (r * r)
    q = r * theta * (1.0 + (0.0 if math.isinf(alpha) else 1.0 / alpha))
    robot = tr.Robot(rod_of(p, kirchhoff=kirchhoff), [tr.Tendon(offset=r, EA=EA, slope=slope)])
    return tr.Scene(robot, displacement=[q], loads=[tr.PointLoad(s=L, force=tuple(F))])


#: Scenes beyond the model's validity. For a Kirchhoff rod with one parallel tendon
#: anchored at a moment-free tip, moment balance there gives the tip curvature
#: kappa(L) = tau r / EI, so the tendon's path-length rate |w| = 1 - kappa r reaches
#: zero when the tension reaches EI / r^2 (120.6 N for the Fig. 11 robot): the tendon
#: would pass through the centre of curvature. These loads need more tension than
#: that on their loading path (measured: the continuation stalls at tau = 116-120 N),
#: so no valid equilibrium is reachable; the solver must say so.
KAPPA_R_LIMIT = {("90deg", "transverse-x"), ("90deg", "axial+z"), ("straight", "transverse-x")}
KAPPA_R_WORDS = ("curvature", "1/r", "centre of curvature", "center of curvature", "ei/r")


def stress_cases() -> list[StressCase]:
    """Every stress case (the issue's list, each dimension swept)."""
    tr = _tr()
    cases: list[StressCase] = []
    p = FIG11
    L, EI, r = p["L"], EI_of(p), p["r"]
    fs = EI / L**2  # force scale [N]

    # 1. tendon stiffness r^2 k L / EI from 1e-2 to 1e12, and inextensible; bent to 90 deg,
    #    with an in-plane and an out-of-plane tip load F L^2/EI = 1.
    for a in [1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3, 1e4, 1e6, 1e8, 1e10, 1e12, math.inf]:
        for lab, F in (("inplane", (-fs, 0.0, 0.0)), ("outofplane", (0.0, fs, 0.0))):
            nm = f"stiffness/alpha={a:g}/{lab}"
            cases.append(
                StressCase(
                    nm,
                    "tendon stiffness",
                    (lambda a=a, F=F: (_one_tendon_scene(p, math.pi / 2, a, F), _stress_opts())),
                    quick=(a in (1e-2, 1e12, math.inf) and lab == "inplane"),
                )
            )
    # 2. actuation from straight to a 270 deg curl, unloaded (exact: a circle) and loaded.
    for deg in [0, 45, 90, 180, 270]:
        th = math.radians(deg)
        for kirch in (True, False):
            nm = f"actuation/{deg}deg/{'kirchhoff' if kirch else 'cosserat'}"

            def chk(sol, th=th, kirch=kirch):
                # Kirchhoff: theta_L = q/r exactly, the shape is a circle of curvature theta/L.
                if not kirch:
                    return math.nan, True, "no closed form (backbone compression)"
                pos, _ = refs.circle_end_moment(L, EI, (0.0, max(th, 1e-300) * EI / L, 0.0))
                e = float(np.linalg.norm(sol.tip_position - pos[0]) / L)
                return e, e < 1e-6, "vs exact circle"

            cases.append(
                StressCase(
                    nm,
                    "actuation",
                    (
                        lambda th=th, kirch=kirch: (
                            _one_tendon_scene(p, th, kirchhoff=kirch),
                            _stress_opts(),
                        )
                    ),
                    check=chk,
                    quick=(deg == 270 and kirch),
                )
            )
            nm = f"actuation/{deg}deg/{'kirchhoff' if kirch else 'cosserat'}/loaded-outofplane"
            cases.append(
                StressCase(
                    nm,
                    "actuation",
                    (
                        lambda th=th, kirch=kirch: (
                            _one_tendon_scene(p, th, F=(0.0, fs, 0.0), kirchhoff=kirch),
                            _stress_opts(),
                        )
                    ),
                )
            )
    # 3. loads up to F L^2/EI = 100, in-plane transverse, axial (both signs), out-of-plane,
    #    on the 90 deg actuated robot and on the straight robot.
    for mag in [1.0, 10.0, 30.0, 100.0]:
        for lab, d in (
            ("transverse-x", (-1, 0, 0)),
            ("transverse+x", (1, 0, 0)),
            ("axial-z", (0, 0, -1)),
            ("axial+z", (0, 0, 1)),
            ("outofplane", (0, 1, 0)),
        ):
            F = tuple(mag * fs * c for c in d)
            for th, tl in ((math.pi / 2, "90deg"), (0.0, "straight")):
                nm = f"load/{tl}/{lab}/FL2EI={mag:g}"
                chk = None
                if tl == "straight" and lab in ("outofplane", "transverse+x"):
                    # the tendon at +x stays at its length (out of plane: on the neutral axis)
                    # or shortens (slack), so the robot is the plain elastica: exact
                    ax = 1 if lab == "outofplane" else 0

                    def chk(sol, mag=mag, ax=ax):
                        x, z, _ = refs.elastica_tip_force(L, EI, mag * fs)
                        ref = np.zeros(3)
                        ref[ax] = x
                        ref[2] = z
                        e = float(np.linalg.norm(sol.tip_position - ref) / L)
                        return e, e < 1e-6, "vs exact elastica"

                wp, words = True, ()
                if (mag == 100.0 and (tl, lab) in KAPPA_R_LIMIT) or (
                    mag == 30.0 and (tl, lab) == ("90deg", "transverse-x")
                ):
                    # (the 90 deg robot under -x reaches tau = EI/r^2 at F L^2/EI ~ 26 on its path)
                    wp, words = False, KAPPA_R_WORDS
                elif mag == 100.0 and (tl, lab) == ("90deg", "transverse+x"):
                    # the tendon goes nearly slack and the path snaps at F L^2/EI ~ 58
                    # (limit point); no continuous loading path reaches 100
                    wp, words = False, ("limit point", "snap")
                cases.append(
                    StressCase(
                        nm,
                        "loads",
                        (lambda th=th, F=F: (_one_tendon_scene(p, th, F=F), _stress_opts())),
                        check=chk,
                        well_posed=wp,
                        expect_words=words,
                        quick=(
                            mag == 100.0 and tl == "90deg" and lab in ("transverse-x", "outofplane")
                        ),
                    )
                )
    # 3b. the plain cantilever (no tendon) under a transverse tip force: exact elastica.
    for mag in [5.0, 10.0, 12.0, 30.0, 100.0]:

        def chk_ela(sol, mag=mag):
            x, z, _ = refs.elastica_tip_force(L, EI, mag * fs)
            e = float(np.linalg.norm(sol.tip_position - np.array([x, 0.0, z])) / L)
            return e, e < 1e-6, "vs exact elastica"

        cases.append(
            StressCase(
                f"load/plain-rod/transverse/FL2EI={mag:g}",
                "loads",
                (
                    lambda mag=mag: (
                        tr.Scene(
                            tr.Robot(rod_of(p), []),
                            loads=[tr.PointLoad(s=L, force=(mag * fs, 0.0, 0.0))],
                        ),
                        _stress_opts(),
                    )
                ),
                check=chk_ela,
                quick=(mag == 30.0),
            )
        )
    # 4. tensile axial tip loads, L sqrt(T/EI) up to 20, on a plain rod with a transverse
    #    tip force (exact reference by collocation) and on the 45 deg actuated robot.
    for lam in [1.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0]:
        T = lam**2 * fs
        nm = f"tension/plain/Lsqrt(T/EI)={lam:g}"

        def chk_bvp(sol, T=T):
            x, z, th, _ = refs.planar_rod_bvp(L, EI, (fs, T), tol=1e-11, nodes=800)
            e = float(np.hypot(sol.tip_position[0] - x, sol.tip_position[2] - z) / L)
            return e, e < 1e-6, "vs collocation (solve_bvp)"

        cases.append(
            StressCase(
                nm,
                "tensile load",
                (
                    lambda T=T: (
                        tr.Scene(
                            tr.Robot(rod_of(p), []), loads=[tr.PointLoad(s=L, force=(fs, 0.0, T))]
                        ),
                        _stress_opts(),
                    )
                ),
                check=chk_bvp,
                quick=(lam in (7.0, 20.0)),
            )
        )
        nm = f"tension/actuated45/Lsqrt(T/EI)={lam:g}"
        # from L sqrt(T/EI) ~ 12 the tendon would need more than EI/r^2 (see KAPPA_R_LIMIT)
        cases.append(
            StressCase(
                nm,
                "tensile load",
                (lambda T=T: (_one_tendon_scene(p, math.pi / 4, F=(0.0, 0.0, T)), _stress_opts())),
                quick=(lam == 20.0),
                well_posed=lam < 15.0,
                expect_words=KAPPA_R_WORDS,
            )
        )
    # 5. load ramps across the taut/slack switch and back (Fig. 17 robot), warm started.
    cases.append(
        StressCase("ramp/fig17/taut-slack-taut", "slack switch", None, ramp=_ramp_fig17, quick=True)
    )
    cases.append(
        StressCase(
            "ramp/fig17/taut-slack-taut/squared",
            "slack switch",
            None,
            ramp=lambda: _ramp_fig17(slack_model="squared"),
        )
    )
    cases.append(
        StressCase(
            "ramp/fig17/cold-each", "slack switch", None, ramp=lambda: _ramp_fig17(warm=False)
        )
    )
    # 5b. a warm-started sweep of a large transverse load on the plain rod (exact elastica)
    cases.append(
        StressCase(
            "ramp/plain-rod/FL2EI=31.6->100/warm-10%",
            "loads",
            None,
            ramp=_ramp_large_load,
            quick=True,
        )
    )
    # 6. opposing inextensible tendons on a Kirchhoff backbone (statically indeterminate or
    #    without equilibrium) and the well-posed neighbours.
    for q, wp, words in (
        (0.0, False, ("indetermin",)),
        (1e-3, False, ("equilibrium", "indetermin")),
        (-1e-3, True, ()),
    ):
        nm = f"opposing/kirchhoff-inextensible/q1=q2={q:g}"
        cases.append(
            StressCase(
                nm,
                "opposing tendons",
                (lambda q=q: (_opposing(p, q, q), _stress_opts())),
                well_posed=wp,
                expect_words=words,
                quick=(q == 0.0),
            )
        )
    # loaded: one tendon tightens and locks the tip angle at 0, so the other keeps its
    # length exactly; the difference of the tensions is fixed, their common level is not
    cases.append(
        StressCase(
            "opposing/kirchhoff-inextensible/q1=q2=0/loaded",
            "opposing tendons",
            lambda: (_opposing(p, 0.0, 0.0, F=(fs, 0.0, 0.0)), _stress_opts()),
            well_posed=False,
            expect_words=("indetermin",),
            quick=True,
        )
    )
    cases.append(
        StressCase(
            "opposing/cosserat-inextensible/q1=q2=1mm",
            "opposing tendons",
            lambda: (_opposing(p, 1e-3, 1e-3, kirchhoff=False), _stress_opts()),
        )
    )
    cases.append(
        StressCase(
            "opposing/kirchhoff-EA-finite/q1=q2=1mm",
            "opposing tendons",
            lambda: (_opposing(p, 1e-3, 1e-3, EA=1e4 * EI / r**2), _stress_opts()),
        )
    )
    # 7. Fig. 12: straight robot, three tendons at q = 0, pure twisting moment, tendon
    #    stiffness growing without bound (inextensible: no equilibrium with M != 0).
    for a in [1.0, 1e2, 1e4, 1e6, 1e8, 1e12, math.inf]:
        nm = f"fig12/twist/alpha={a:g}"
        chk12 = None
        if not math.isinf(a):

            def chk12(sol, a=a):
                rod = sol.scene.robot.rod
                EA = a * EI / r**2
                Mz = sol.scene.point_loads[0].moment[2]
                psi, T = refs.twist_with_tendons(L, rod.torsional_stiffness, EA, r, 3, Mz)
                Rt = sol.tip_rotation
                psi_sol = math.atan2(Rt[1, 0], Rt[0, 0])
                e = max(abs(psi_sol - psi) / psi, float(np.max(np.abs(sol.tension - T))) / T)
                # exact solution; 1e-6 relative is the verification threshold used throughout
                return e, e < 1e-6, "twist and tension vs the exact helix solution"

        cases.append(
            StressCase(
                nm,
                "Fig. 12 twist",
                (lambda a=a: (_fig12(p, a), _stress_opts())),
                well_posed=not math.isinf(a),
                check=chk12,
                expect_words=("equilibrium", "indetermin", "singular", "twist"),
                quick=(a in (1e12, math.inf)),
            )
        )
    # 8. slenderness L/d from 10 to 1e4 (Cosserat backbone: shear and extension matter at 10).
    for sl in [10, 30, 100, 1e3, 1e4]:
        pp = dict(p)
        pp["d"] = p["L"] / sl
        pp["r"] = max(p["r"], 0.6 * pp["d"])  # channel outside the section
        fsl = EI_of(pp) / L**2
        for lab, F in (("inplane", (-fsl, 0.0, 0.0)), ("outofplane", (0.0, fsl, 0.0))):
            nm = f"slenderness/L/d={sl:g}/{lab}"
            cases.append(
                StressCase(
                    nm,
                    "slenderness",
                    (
                        lambda pp=pp, F=F: (
                            _one_tendon_scene(pp, math.pi / 2, F=F, kirchhoff=False),
                            _stress_opts(),
                        )
                    ),
                    quick=(sl in (10, 1e4) and lab == "outofplane"),
                )
            )
    # 9. tendon offsets from 1e-4 L to 0.3 L (90 deg, F L^2/EI = 1 in-plane), Kirchhoff and Cosserat.
    for rr in [1e-4, 1e-3, 1e-2, 0.1, 0.3]:
        for kirch in (True, False):
            nm = f"offset/r={rr:g}L/{'kirchhoff' if kirch else 'cosserat'}"
            cases.append(
                StressCase(
                    nm,
                    "tendon offset",
                    (
                        lambda rr=rr, kirch=kirch: (
                            _one_tendon_scene(
                                p, math.pi / 2, F=(-fs, 0.0, 0.0), r=rr * L, kirchhoff=kirch
                            ),
                            _stress_opts(),
                        )
                    ),
                    quick=(rr in (1e-4, 0.3) and kirch),
                )
            )
    # 10. loads of 1e-6 N on the straight robot (closed form known) and on the 90 deg robot.
    for lab, F in (
        ("transverse", (-1e-6, 0.0, 0.0)),
        ("outofplane", (0.0, 1e-6, 0.0)),
        ("axial", (0.0, 0.0, -1e-6)),
    ):
        nm = f"tiny/straight/{lab}/1e-6N"
        if lab == "outofplane":

            def chk(sol):
                # bending about x leaves the tendon at +x on the neutral axis (its length does
                # not change to first order), so the tip moves F L^3/(3 EI) like a plain rod
                d = 1e-6 * L**3 / (3 * EI)
                e = abs(sol.tip_position[1] - d) / d
                return e, e < 1e-6, "deflection vs F L^3/(3 EI)"
        elif lab == "axial":

            def chk(sol):
                # a compressive load far below Euler's leaves the Kirchhoff rod straight
                e = float(
                    np.hypot(sol.tip_position[0], sol.tip_position[1]) / L
                    + abs(sol.tip_position[2] - L) / L
                )
                return e, e < 1e-12, "straight under axial load"

        if lab == "transverse":

            def chk(sol):
                d = float(refs.small_load_deflection(L, 1e-6, L, L, EI, 0.0, r, np.inf))
                e = abs(-sol.tip_position[0] - d) / d
                # F L^2/EI = 8e-7: the closed form is exact to ~1e-12 of the deflection;
                # 1e-6 allows the solver's scaled stopping test, not an unscaled one.
                return e, e < 1e-6, "deflection vs closed form eq. 12"

        cases.append(
            StressCase(
                nm,
                "tiny loads",
                (
                    lambda F=F: (
                        tr.Scene(
                            tr.Robot(rod_of(p), [tr.Tendon(offset=r)]),
                            displacement=[0.0],
                            loads=[tr.PointLoad(s=L, force=F)],
                        ),
                        _stress_opts(),
                    )
                ),
                check=chk,
                quick=(lab == "transverse"),
            )
        )
        nm = f"tiny/90deg/{lab}/1e-6N"
        cases.append(
            StressCase(
                nm,
                "tiny loads",
                (lambda F=F: (_one_tendon_scene(p, math.pi / 2, F=F), _stress_opts())),
                check=_tiny_vs_unloaded(F),
            )
        )
    return cases


def _tiny_vs_unloaded(F):
    """A 1e-6 N load on the 90 deg robot: compare the tip displacement with the one
    the compliance predicts (dx = C F). Catches solvers that stop before a tiny load
    has moved the tip."""

    def chk(sol):
        tr = _tr()
        sc0 = tr.Scene(sol.scene.robot, displacement=sol.scene.displacement)
        s0 = _solve_quiet(sc0, tr.Options(tol=1e-13))
        C = tr.compliance(sc0, options=tr.Options(tol=1e-13))
        dx_pred = C[:3, :3] @ np.asarray(F)
        dx = sol.tip_position - s0.tip_position
        n = np.linalg.norm(dx_pred)
        e = float(np.linalg.norm(dx - dx_pred) / n)
        # the load is 1e-6 of EI/L^2, so the linearisation error is ~1e-6 relative;
        # 1e-3 catches a solver that leaves the tip where the unloaded robot had it.
        return e, e < 1e-3, "tip displacement vs compliance x load"

    return chk


def _opposing(p, q1, q2, F=(0.0, 0.0, 0.0), kirchhoff=True, EA=math.inf):
    tr = _tr()
    L, r = p["L"], p["r"]
    robot = tr.Robot(
        rod_of(p, kirchhoff=kirchhoff),
        [tr.Tendon(offset=r, angle=0.0, EA=EA), tr.Tendon(offset=r, angle=math.pi, EA=EA)],
    )
    return tr.Scene(robot, displacement=[q1, q2], loads=[tr.PointLoad(s=L, force=F)])


def _fig12(p, alpha, Mz_scale=0.5):
    """Paper Fig. 12: straight Kirchhoff robot, three tendons at q = 0, tip moment M_z =
    0.5 GJ/L (a half-radian twist without tendons)."""
    tr = _tr()
    L, r, EI = p["L"], p["r"], EI_of(p)
    rod = rod_of(p)
    EA = math.inf if math.isinf(alpha) else alpha * EI / r**2
    tendons = [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)]
    Mz = Mz_scale * rod.torsional_stiffness / L
    return tr.Scene(
        tr.Robot(rod, tendons),
        displacement=[0.0, 0.0, 0.0],
        loads=[tr.PointLoad(s=L, moment=(0.0, 0.0, Mz))],
    )


def _ramp_fig17(slack_model="linear", warm=True, n=13):
    """Fig. 17 scene: load ramp 0 -> 2 P_c -> 0 (P_c the critical load), warm started
    along the ramp. Checks: every step converges and verifies; the tension is positive
    below P_c and zero above (within a step); the way back retraces the way up."""
    tr = _tr()
    p = FIG17
    L, EI, r = p["L"], EI_of(p), p["r"]
    Pc = refs.critical_tip_angle_load(L, EI, math.pi / 2)
    up = list(np.linspace(0.0, 2.0 * Pc, n))
    path = up + up[-2::-1]
    robot = tr.Robot(rod_of(p), [tr.Tendon(offset=r)])
    prev = None
    recs = []
    opts = tr.Options(slack_model=slack_model)
    t0 = time.perf_counter()
    for P in path:
        sc = tr.Scene(
            robot, displacement=[r * math.pi / 2], loads=[tr.PointLoad(s=L, force=(0.0, 0.0, -P))]
        )
        sol = _solve_quiet(sc, opts, guess=prev if warm else None)
        v = (
            verify(sol)
            if sol.success
            else dict(verified=False, balance=math.nan, refine=math.nan, note="")
        )
        recs.append((P, sol, v))
        if sol.success:
            prev = sol
    secs = time.perf_counter() - t0
    ok = all(s.success for _, s, _ in recs)
    ver = all(v["verified"] for _, _, v in recs)
    notes = []
    # tension sign pattern against the critical load (independent, elliptic integrals)
    bad_t = [
        P
        for P, s, _ in recs
        if s.success
        and ((P < 0.98 * Pc and s.tension[0] <= 0.0) or (P > 1.02 * Pc and s.tension[0] > 1e-9))
    ]
    if bad_t:
        notes.append(f"tension wrong side of P_c={Pc:.4f} N at P={bad_t}")
    # up and down agree
    m = len(up)
    back = [
        float(np.linalg.norm(recs[i][1].tip_position - recs[len(path) - 1 - i][1].tip_position) / L)
        for i in range(m)
        if recs[i][1].success and recs[len(path) - 1 - i][1].success
    ]
    hyst = max(back) if back else math.nan
    if not (hyst < 1e-6):
        notes.append(f"ramp up and down differ by {hyst:.2e} L")
    # past P_c the tip must be the free elastica (exact)
    errs = []
    for P, s, _ in recs:
        if P > 1.02 * Pc and s.success:
            x, z, _ = refs.elastica_compressive(L, EI, P)
            errs.append(float(np.hypot(s.tip_position[0] - x, s.tip_position[2] - z) / L))
    e_ela = max(errs) if errs else math.nan
    if not (e_ela < 1e-6):
        notes.append(f"slack tip differs from the exact elastica by {e_ela:.2e} L")
    verified = ok and ver and not notes
    fails = [f"P={P:.3f}: {s.message}" for P, s, _ in recs if not s.success]
    msg = (
        "; ".join(fails[:3] + notes)
        or f"{len(path)} steps 0 -> {2 * Pc:.3f} N -> 0 (P_c={Pc:.4f} N)"
    )
    return dict(
        converged=ok,
        verified=verified,
        iterations=int(sum(s.nit for _, s, _ in recs)),
        nfev=int(sum(s.nfev for _, s, _ in recs)),
        residual=float(max((s.residual_norm for _, s, _ in recs), default=math.nan)),
        jacobian_cond=float(
            max(
                (s.jacobian_cond for _, s, _ in recs if np.isfinite(s.jacobian_cond)),
                default=math.nan,
            )
        ),
        seconds=secs,
        balance=float(
            max((v["balance"] for _, _, v in recs if np.isfinite(v["balance"])), default=math.nan)
        ),
        refine=float(
            max((v["refine"] for _, _, v in recs if np.isfinite(v["refine"])), default=math.nan)
        ),
        check_error=e_ela,
        message=msg,
        continuation_steps=int(sum(s.continuation_steps for _, s, _ in recs)),
    )


def _ramp_large_load(n=13):
    """Plain Kirchhoff rod (Fig. 17 section), transverse tip load (-x) swept from
    F L^2/EI = 31.6 to 100 in 10 % steps, each solve warm started from the previous
    one (what a design sweep does). Every step must converge on the exact elastica
    (elliptic integrals): a warm start that jumps to another equilibrium is a wrong
    answer (finding S7)."""
    tr = _tr()
    p = FIG17
    L, EI = p["L"], EI_of(p)
    robot = tr.Robot(rod_of(p), [])
    prev = None
    errs, recs = [], []
    t0 = time.perf_counter()
    for fl in np.geomspace(10**1.5, 100.0, n):
        F = fl * EI / L**2
        sol = _solve_quiet(
            tr.Scene(robot, loads=[tr.PointLoad(s=L, force=(-F, 0.0, 0.0))]),
            tr.Options(),
            guess=prev,
        )
        recs.append(sol)
        if not sol.success:
            errs.append(math.nan)
            break
        x, z, _ = refs.elastica_tip_force(L, EI, F)
        errs.append(float(np.hypot(sol.tip_position[0] + x, sol.tip_position[2] - z) / L))
        prev = sol
    secs = time.perf_counter() - t0
    ok = all(s.success for s in recs) and len(recs) == n
    worst = max((e for e in errs if np.isfinite(e)), default=math.nan)
    bad = [f"{fl:.3g}" for fl, e in zip(np.geomspace(10**1.5, 100.0, n), errs) if not (e < 1e-6)]
    msg = (
        f"{len(recs)} warm-started steps; worst tip error vs the exact elastica {worst:.2e} L"
        + (f"; wrong or failed at F L^2/EI = {', '.join(bad)}" if bad else "")
        + ("" if ok else f"; last message: {recs[-1].message}")
    )
    return dict(
        converged=ok,
        verified=ok and not bad,
        iterations=int(sum(s.nit for s in recs)),
        nfev=int(sum(s.nfev for s in recs)),
        residual=float(max(s.residual_norm for s in recs)),
        jacobian_cond=float(recs[-1].jacobian_cond),
        seconds=secs,
        balance=math.nan,
        refine=math.nan,
        check_error=worst,
        message=msg,
        continuation_steps=int(sum(s.continuation_steps for s in recs)),
    )


# --------------------------------------------------------------------------- verification
def _tendon_tangents(sol, s_index=0):
    """Unit tendon tangents (world) at node ``s_index`` from the solution's own strains."""
    sc = sol.scene
    rod = sc.robot.rod
    R = sol.rotation[s_index]
    n_b = R.T @ sol.force[s_index]
    m_b = R.T @ sol.moment[s_index]
    EI, GJ = rod.bending_stiffness, rod.torsional_stiffness
    u = m_b / np.array([EI, EI, GJ])
    if rod.kirchhoff:
        v = np.array([0.0, 0.0, 1.0])
    else:
        inv = np.array(
            [1.0 / rod.shear_stiffness, 1.0 / rod.shear_stiffness, 1.0 / rod.axial_stiffness]
        )
        v = np.array([0.0, 0.0, 1.0]) + inv * n_b
    s = sol.s[s_index]
    out = []
    for t in sc.robot.tendons:
        d = np.array([math.cos(t.angle), math.sin(t.angle), 0.0])
        rr = (t.slope * s + t.offset) * d
        w = np.cross(u, rr) + t.slope * d + v
        out.append((R @ rr, R @ (w / np.linalg.norm(w))))
    return out


def global_balance(sol):
    """Scaled residual of the whole robot's force and moment balance (world frame,
    about the base): base reaction, tendon pulls at the base, point loads at the
    solved positions, distributed load (Simpson over the nodes). Scaled by the
    largest force present (loads, tensions; EI/L^2 only if there is none) and that
    times L, so that a 1e-6 N load that the solver ignored shows as an O(1) error."""
    sc = sol.scene
    L = sc.robot.rod.length
    EI = sc.robot.rod.bending_stiffness
    if sol.s[0] != 0.0 or abs(sol.s[-1] - L) > 1e-12 * L:
        raise ValueError("global_balance needs nodes spanning [0, L]")
    Fsum = -sol.force[0].copy()
    Msum = -sol.moment[0].copy()
    fmax = 0.0
    for (rb, tb), tau in zip(_tendon_tangents(sol, 0), sol.tension):
        Fsum -= tau * tb
        Msum -= tau * np.cross(rb, tb)
        fmax = max(fmax, abs(tau))
    for pl in sc.point_loads:
        i = int(np.argmin(np.abs(sol.s - pl.s)))
        if abs(sol.s[i] - pl.s) > 1e-12 * L:
            pos = sol.at(pl.s).position
        else:
            pos = sol.position[i]
        Fsum += np.asarray(pl.force)
        Msum += np.cross(pos, pl.force) + np.asarray(pl.moment)
        fmax = max(fmax, float(np.linalg.norm(pl.force)), float(np.linalg.norm(pl.moment)) / L)
    f = sc.distributed_force
    if np.any(f != 0.0):
        from scipy.integrate import simpson

        Fsum += f * L
        Msum += np.cross(simpson(sol.position, x=sol.s, axis=0), f)
        fmax = max(fmax, float(np.linalg.norm(f)) * L)
    if fmax == 0.0:  # nothing loads the robot: compare with its natural force scale
        fmax = EI / L**2
    return float(max(np.linalg.norm(Fsum) / fmax, np.linalg.norm(Msum) / (fmax * L)))


#: Verification thresholds (relative). A verified answer balances to 1e-6 of the
#: largest force (the default integrator's truncation error is ~1e-8; 1e-6 leaves
#: room for the extreme cases while still catching wrong answers, which are off by
#: O(1)), and its tip moves by less than 1e-6 L when the steps are doubled and when
#: the adaptive integrator at rtol 1e-10 is used instead.
BALANCE_TOL = 1e-6
REFINE_TOL = 1e-6


def verify(sol, check=None):
    """Verification of a converged solution (see module docstring). Returns a dict."""
    tr = _tr()
    out = dict(verified=False, balance=math.nan, refine=math.nan, check_error=math.nan, note="")
    arrays = [sol.position, sol.rotation, sol.force, sol.moment, sol.tension, sol.slack]
    if not all(np.all(np.isfinite(a)) for a in arrays):
        out["note"] = "NaN/inf in a successful result"
        return out
    sc = sol.scene
    L = sc.robot.rod.length
    notes = []
    try:
        out["balance"] = global_balance(sol)
    except Exception as exc:  # noqa: BLE001
        notes.append(f"balance check failed: {exc}")
    # refinement: double the steps the solve used; and the adaptive integrator.
    diffs = []
    steps = max(int(sol.formulation.steps), 1)
    o = sol.options
    for kw in (
        dict(integrator=o.integrator if o.integrator != "adaptive" else "rk8", steps=2 * steps),
        dict(integrator="adaptive", rtol=1e-10),
    ):
        kk = o.raw()
        kk.update(kw)
        # the comparison is at 1e-6: 1e-8 is tight enough, and the adaptive integrator's
        # residual is noisy at its rtol level, so a tighter tol can stall on round-off
        kk["tol"] = max(o.tol, 1e-8)
        kk["tip_only"] = False
        s2 = _solve_quiet(sc, tr.Options(**kk), guess=sol)
        if not s2.success:
            notes.append(f"refined solve ({kw}) failed: {s2.message}")
            diffs.append(math.inf)
            continue
        d = float(np.linalg.norm(s2.tip_position - sol.tip_position) / L)
        if sol.tension.size:
            tscale = max(float(np.max(np.abs(s2.tension))), EI_scale(sc))
            d = max(d, float(np.max(np.abs(s2.tension - sol.tension))) / tscale)
        diffs.append(d)
    out["refine"] = max(diffs) if diffs else math.nan
    ok = out["balance"] < BALANCE_TOL and out["refine"] < REFINE_TOL
    if not out["balance"] < BALANCE_TOL:
        notes.append(f"global balance residual {out['balance']:.2e}")
    if not out["refine"] < REFINE_TOL:
        notes.append(f"refinement changes the answer by {out['refine']:.2e}")
    R = sol.rotation
    orth = float(np.max(np.abs(np.einsum("nij,nik->njk", R, R) - np.eye(3))))
    if orth > 1e-6:
        ok = False
        notes.append(f"rotation not orthonormal ({orth:.1e})")
    if (
        np.any(sol.tension < 0)
        or np.any(sol.slack < 0)
        or np.any((sol.tension > 0) & (sol.slack > 0))
    ):
        ok = False
        notes.append("tension/slack complementarity violated")
    if check is not None:
        try:
            e, cok, what = check(sol)
            out["check_error"] = e
            if not cok:
                ok = False
                notes.append(f"{what}: error {e:.2e}")
        except Exception as exc:  # noqa: BLE001
            ok = False
            notes.append(f"check raised {type(exc).__name__}: {exc}")
    out["verified"] = bool(ok)
    out["note"] = "; ".join(notes)
    return out


def EI_scale(scene):
    rod = scene.robot.rod
    return rod.bending_stiffness / rod.length**2


def run_case(case: StressCase) -> dict:
    """Run one stress case in this process (the child of :func:`run_case_isolated`)."""
    rec = dict(case=case.name, group=case.group, well_posed=case.well_posed)
    try:
        if case.ramp is not None:
            r = case.ramp()
            rec.update(r)
        else:
            scene, opts = case.build()
            t0 = time.perf_counter()
            sol = _solve_quiet(scene, opts)
            rec["seconds"] = time.perf_counter() - t0
            finite = all(np.all(np.isfinite(a)) for a in (sol.position, sol.tension))
            rec.update(
                converged=bool(sol.success),
                iterations=sol.nit,
                nfev=sol.nfev,
                residual=sol.residual_norm,
                jacobian_cond=sol.jacobian_cond,
                continuation_steps=sol.continuation_steps,
                message=sol.message,
                status=sol.status,
                formulation=repr(sol.formulation),
            )
            if sol.success:
                v = verify(sol, case.check)
                rec.update(
                    verified=v["verified"],
                    balance=v["balance"],
                    refine=v["refine"],
                    check_error=v["check_error"],
                )
                if v["note"]:
                    rec["message"] = f"{sol.message} | {v['note']}"
            else:
                rec.update(verified=False, balance=math.nan, refine=math.nan, check_error=math.nan)
                rec["finite_on_failure"] = finite
    except ValueError as exc:
        # the API rejects the scene before any C runs: honest for an ill-posed scene
        # (the message must then name the problem), a finding for a well-posed one
        rec.update(
            converged=False,
            verified=False,
            message=f"ValueError before solving: {exc}",
            outcome="honest failure" if not case.well_posed else "REJECTED",
        )
    except Exception as exc:  # noqa: BLE001 - an exception is itself a finding
        rec.update(
            converged=False,
            verified=False,
            outcome="exception",
            message=f"{type(exc).__name__}: {exc}",
            traceback=traceback.format_exc(),
        )
    rec["outcome"] = rec.get("outcome") or classify(rec)
    return rec


def classify(rec):
    """outcome: 'verified' (well-posed, converged, verified), 'honest failure'
    (ill-posed, success False, message with an expected word), and the bad ones:
    'UNVERIFIED' (converged to something that fails verification), 'FAILED'
    (well-posed but did not converge), 'WRONG SUCCESS' (ill-posed but success),
    'VAGUE FAILURE' (ill-posed, failed, message without the diagnosis), 'REJECTED'
    (well-posed but the API raised ValueError)."""
    if rec.get("outcome") in ("exception", "timeout", "REJECTED", "honest failure"):
        return rec["outcome"]
    if rec["well_posed"]:
        if rec.get("converged"):
            return "verified" if rec.get("verified") else "UNVERIFIED"
        return "FAILED"
    if rec.get("converged"):
        return "WRONG SUCCESS"
    return "honest failure"


def _child(case_name, conn, quick):
    try:
        case = {c.name: c for c in stress_cases()}[case_name]
        rec = run_case(case)
        if case.expect_words and rec["outcome"] == "honest failure":
            msg = rec.get("message", "").lower()
            if not any(w in msg for w in case.expect_words):
                rec["outcome"] = "VAGUE FAILURE"
        conn.send(rec)
    except BaseException as exc:  # noqa: BLE001
        conn.send(
            dict(
                case=case_name,
                outcome="exception",
                converged=False,
                verified=False,
                message=f"{type(exc).__name__}: {exc}",
                traceback=traceback.format_exc(),
            )
        )
    finally:
        conn.close()


def run_case_isolated(case: StressCase, timeout: float) -> dict:
    """Run ``case`` in a child process; kill it after ``timeout`` seconds (a hang is a
    finding: outcome 'timeout'). A crash of the child (segfault) is outcome 'crash'."""
    import multiprocessing as mp

    ctx = mp.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)
    t0 = time.perf_counter()
    proc = ctx.Process(target=_child, args=(case.name, child, False))
    proc.start()
    child.close()
    rec = None
    if parent.poll(timeout):
        try:
            rec = parent.recv()
        except EOFError:
            rec = None
    wall = time.perf_counter() - t0
    if proc.is_alive():
        proc.join(1.0)
    if proc.is_alive():
        proc.kill()
        proc.join()
    if rec is None:
        if wall >= timeout:
            rec = dict(outcome="timeout", message=f"no answer within {timeout:g} s (killed)")
        else:
            rec = dict(outcome="crash", message=f"child process died (exit code {proc.exitcode})")
        rec.update(case=case.name, converged=False, verified=False, seconds=wall)
    rec.setdefault("group", case.group)
    rec.setdefault("well_posed", case.well_posed)
    rec["wall_seconds"] = wall
    return rec


STRESS_COLS = [
    "case",
    "group",
    "well_posed",
    "outcome",
    "converged",
    "verified",
    "iterations",
    "nfev",
    "residual",
    "jacobian_cond",
    "seconds",
    "wall_seconds",
    "continuation_steps",
    "balance",
    "refine",
    "check_error",
    "message",
]

GOOD = ("verified", "honest failure")


def run_stress(out: str, quick: bool = False, timeout: float = 60.0, only: str = "", log=print):
    os.makedirs(out, exist_ok=True)
    cases = [c for c in stress_cases() if (c.quick or not quick) and (only in c.name)]
    rows = []
    for c in cases:
        rec = run_case_isolated(c, timeout)
        rows.append(rec)
        flag = "  " if rec["outcome"] in GOOD else "!!"
        log(
            f"{flag} {c.name:55s} {rec['outcome']:15s} nit {rec.get('iterations', '-')!s:>4} "
            f"t {rec.get('seconds', math.nan) * 1e3:9.2f} ms  {str(rec.get('message', ''))[:140]}"
        )
    _write_csv(os.path.join(out, "stress.csv"), rows, STRESS_COLS)
    plot_stress(rows, os.path.join(out, "stress.png"))
    bad = [r for r in rows if r["outcome"] not in GOOD]
    log(
        f"{len(rows)} cases: {len(rows) - len(bad)} good (verified or honest failure), {len(bad)} not"
    )
    return rows


def plot_stress(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colors = {
        "verified": "tab:green",
        "honest failure": "tab:olive",
        "UNVERIFIED": "tab:orange",
        "FAILED": "tab:red",
        "WRONG SUCCESS": "tab:purple",
        "VAGUE FAILURE": "gold",
        "exception": "black",
        "timeout": "tab:brown",
        "crash": "black",
        "REJECTED": "tab:pink",
    }
    n = len(rows)
    fig, ax = plt.subplots(figsize=(10, max(4.0, 0.13 * n + 1.2)))
    y = np.arange(n)[::-1]
    secs = [
        max(
            float(r.get("seconds", math.nan) if r.get("seconds") not in (None, "") else math.nan),
            1e-6,
        )
        if np.isfinite(
            float(r.get("seconds", math.nan) if r.get("seconds") not in (None, "") else math.nan)
        )
        else float(r.get("wall_seconds", 1.0))
        for r in rows
    ]
    ax.barh(y, secs, color=[colors.get(r["outcome"], "gray") for r in rows], height=0.8)
    ax.set_xscale("log")
    ax.set_yticks(y)
    ax.set_yticklabels([r["case"] for r in rows], fontsize=6)
    ax.set_xlabel("solve time [s] (log)")
    from matplotlib.patches import Patch

    handles = [
        Patch(color=c, label=f"{k} ({sum(1 for r in rows if r['outcome'] == k)})")
        for k, c in colors.items()
        if any(r["outcome"] == k for r in rows)
    ]
    ax.legend(handles=handles, loc="lower right", fontsize=8)
    ax.set_ylim(-1, n)
    ax.set_title("tendonrod stress suite: outcome and time per case", fontsize=10)
    ax.grid(True, axis="x", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


# --------------------------------------------------------------------------- CLI
def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m tendonrod bench",
        description="tendonrod benchmarks: work-precision (error vs run time, and "
        "the choice of model) and the stress suite.",
    )
    sub = ap.add_subparsers(dest="which", metavar="{work-precision,stress}")
    sub.required = True
    w = sub.add_parser(
        "work-precision", help="error vs run time per scene, method and setting; model choice"
    )
    w.add_argument("--out", required=True, help="output directory")
    w.add_argument("--quick", action="store_true", help="few settings and repeats (CI)")
    w.add_argument(
        "--repeats", type=int, default=None, help="solves per timing (median); default 7 (quick: 3)"
    )
    w.add_argument("--skip-model-choice", action="store_true", help="only the work-precision chart")
    w.add_argument("--scenes", default="", help="comma-separated scene names (default: all)")
    s = sub.add_parser(
        "stress",
        help="stress suite: every case converges verified or fails honestly",
        epilog="Exit status: 0 if every case is verified or an honest failure, 1 otherwise "
        "(the report is written either way).",
    )
    s.add_argument("--out", required=True, help="output directory")
    s.add_argument("--quick", action="store_true", help="the fast subset (the one the tests run)")
    s.add_argument(
        "--timeout", type=float, default=60.0, help="seconds per case before it counts as a hang"
    )
    s.add_argument("--only", default="", help="run only cases whose name contains this string")
    args = ap.parse_args(argv)
    if args.which == "work-precision":
        names = [x.strip() for x in args.scenes.split(",") if x.strip()]
        run_work_precision(args.out, quick=args.quick, repeats=args.repeats, scenes=names or None)
        if not args.skip_model_choice:
            run_model_choice(args.out, quick=args.quick)
        return 0
    rows = run_stress(args.out, quick=args.quick, timeout=args.timeout, only=args.only)
    return 0 if all(r["outcome"] in GOOD for r in rows) else 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
