"""Work-precision benchmark: error against run time.

Solves a fixed set of scenes (circle under an end moment, elastica under a tip
force, a small load on a straight robot, the paper's Fig. 11 a-c, the Fig. 17
slack scene past its critical load, a three-tendon robot with very stiff tendons
under an out-of-plane load, and robots as built (:mod:`tendonrod.bench.wp_asbuilt`: a
helical tendon, a precurved backbone, a horizontally mounted robot with disk masses), and
channel friction (:mod:`tendonrod.bench.wp_friction`: the exact planar solution, a loaded
displacement-controlled tendon)) with every integrator (rk4 and rk8 over a range of
step counts, the adaptive integrator over a range of rtol) and every Jacobian
option, and records the relative tip error against an exact, closed-form or
independently converged reference (:mod:`tendonrod.bench.references`,
:mod:`tendonrod.bench.reference_robot`, :mod:`tendonrod.analytic`), the median run
time of a cold solve, iterations and evaluations.  Writes ``DIR/work_precision.csv``,
``DIR/work_precision.png`` and ``DIR/work_precision_summary.md``.
"""

from __future__ import annotations

import json
import math
import os
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .. import analytic
from ..model import PointLoad, Robot, Scene, Tendon
from ..options import _JACOBIANS, Options
from . import references as refs
from .common import FIG11, FIG17, EI_of, read_csv, rod_of, solve_quiet, time_solve, write_csv
from .plots import plot_work_precision
from .reference_robot import from_scene
from .wp_asbuilt import asbuilt_scenes
from .wp_friction import friction_scenes


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
    return (
        _exact_scenes()
        + _small_load_scenes()
        + _fig11_scenes()
        + _slack_and_stiff_scenes()
        + asbuilt_scenes(WPScene)
        + friction_scenes(WPScene)
    )


def _exact_scenes() -> list[WPScene]:
    """Circle under an end moment and elastica under a tip force (exact)."""
    scenes = []
    # 1. circle: a pure end moment, exact for any rod (Cosserat backbone here).
    p = FIG11
    L, EI = p["L"], EI_of(p)
    M = (0.0, math.pi * EI / L, 0.0)  # a half circle
    sc = Scene(Robot(rod_of(p, kirchhoff=False), []), loads=[PointLoad(s=L, moment=M)])

    def circle(L=L, EI=EI, M=M):
        return refs.circle_end_moment(L, EI, M)[0][0]

    scenes.append(
        WPScene("circle", "circle: end moment, half turn (exact)", sc, circle, "exact", _tip_scale)
    )
    # 2. elastica: Kirchhoff cantilever, transverse tip force F L^2/EI = 5 (tip angle 70 deg).
    F = 5.0 * EI / L**2
    sc = Scene(Robot(rod_of(p, kirchhoff=True), []), loads=[PointLoad(s=L, force=(F, 0.0, 0.0))])

    def ela(L=L, EI=EI, F=F):
        x, z, _ = refs.elastica_tip_force(L, EI, F)
        return np.array([x, 0.0, z])

    scenes.append(
        WPScene("elastica", "elastica: tip force FL²/EI = 5 (exact)", sc, ela, "exact", _tip_scale)
    )
    return scenes


def _small_load_scenes() -> list[WPScene]:
    """A small load on the straight robot (closed form)."""
    scenes = []
    # 3. small load on the straight robot (Fig. 17 robot, one inextensible parallel
    #    tendon at q = 0): F L^2/EI = 1e-6, so the closed form's own (nonlinear) error is
    #    O((F L^2/EI)^2) = 1e-12 of the deflection. The error is normalised by the
    #    deflection (the tip moves 1e-7 L), transverse components only.
    p = FIG17
    L, EI, r = p["L"], EI_of(p), p["r"]
    F = 1e-6 * EI / L**2
    sc = Scene(
        Robot(rod_of(p), [Tendon(offset=r)]),
        displacement=[0.0],
        loads=[PointLoad(s=L, force=(-F, 0.0, 0.0))],
    )

    def small(L=L, EI=EI, F=F, r=r):
        d = float(analytic.deflection(L, F, L, L, EI, 0.0, r, np.inf))
        return np.array([-d, 0.0, L])

    scenes.append(
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
    return scenes


def _fig11_scenes() -> list[WPScene]:
    """The paper's Fig. 11 a-c (independent ODE references)."""
    scenes = []
    # 4-6. Fig. 11 a-c: actuated by displacement to a 90 deg tip angle.
    p = FIG11
    L, r = p["L"], p["r"]
    q90 = r * math.pi / 2  # inextensible tendon on a Kirchhoff rod: theta_L = q / r exactly
    one = Robot(rod_of(p), [Tendon(offset=r)])
    sc = Scene(one, displacement=[q90], loads=[PointLoad(s=L, force=(-1.0, 0.0, 0.0))])
    scenes.append(
        WPScene(
            "fig11a",
            "Fig. 11a: 90° + transverse 1 N",
            sc,
            _ref_from_scene(sc),
            "independent ODE",
            _tip_scale,
        )
    )
    sc = Scene(one, displacement=[q90], loads=[PointLoad(s=L, force=(0.0, 0.0, -1.0))])
    scenes.append(
        WPScene(
            "fig11b",
            "Fig. 11b: 90° + axial 1 N",
            sc,
            _ref_from_scene(sc),
            "independent ODE",
            _tip_scale,
        )
    )
    scenes.append(
        _three_tendon_scene(
            "fig11c",
            "Fig. 11c: 3 tendons r²kL/(3EI)=50, out-of-plane 0.5 N",
            p,
            alpha=150.0,
            Fy=0.5,
        )
    )
    return scenes


def _slack_and_stiff_scenes() -> list[WPScene]:
    """Fig. 17 past its critical load (exact) and three very stiff tendons."""
    scenes = []
    # 7. Fig. 17 past the critical load: the tendon is slack, the tip is a free elastica.
    p = FIG17
    L, EI, r = p["L"], EI_of(p), p["r"]
    P = 0.5  # critical load is refs.critical_tip_angle_load(L, EI, pi/2) = 0.358 N
    sc = Scene(
        Robot(rod_of(p), [Tendon(offset=r)]),
        displacement=[r * math.pi / 2],
        loads=[PointLoad(s=L, force=(0.0, 0.0, -P))],
    )

    def slack(L=L, EI=EI, P=P):
        x, z, _ = refs.elastica_compressive(L, EI, P)
        return np.array([x, 0.0, z])

    scenes.append(
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
    scenes.append(
        _three_tendon_scene(
            "stiff3", "3 tendons r²kL/EI = 1e8, out-of-plane 0.5 N", FIG11, alpha=1e8, Fy=0.5
        )
    )
    return scenes


def _three_tendon_scene(name, title, p, alpha, Fy, theta=math.pi / 2):
    """Three equally spaced pretensioned parallel tendons (r^2 k L / EI = alpha each,
    k = EA/L) on the Kirchhoff backbone ``p``, bent to ``theta`` by balanced
    displacements, out-of-plane tip force ``Fy`` [N]. Pretension 2 EI theta/(3 r L)
    keeps every tendon taut (the tension change at 90 deg is -EI theta/(1.5 r L)/2
    on the two outer tendons)."""
    L, EI, r = p["L"], EI_of(p), p["r"]
    EA = alpha * EI / (r * r)
    tp = 2.0 * EI * theta / (3.0 * r * L)
    tendons = [Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA, pretension=tp) for i in range(3)]
    q = three_tendon_actuation(EI, L, r, EA, tp, theta)
    sc = Scene(
        Robot(rod_of(p), tendons),
        displacement=q,
        loads=[PointLoad(s=L, force=(0.0, Fy, 0.0))],
    )
    return WPScene(name, title, sc, _ref_from_scene(sc), "independent ODE", _tip_scale)


def _ref_from_scene(sc):
    def f():
        return from_scene(sc).solve().tip_position

    return f


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
    out: list[tuple[str, dict[str, object], float]] = []
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
    """Every Jacobian option of the solver."""
    return list(_JACOBIANS)


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
    """Run the benchmark on ``scenes`` (names; default all) and write its CSV, chart and
    summary to ``out``; returns the rows."""
    os.makedirs(out, exist_ok=True)
    repeats = repeats or (3 if quick else 7)
    allsc = wp_scenes()
    if scenes:
        unknown = set(scenes) - {s.name for s in allsc}
        if unknown:
            raise ValueError(
                f"unknown work-precision scene(s) {sorted(unknown)}; known: {[s.name for s in allsc]}"
            )
    chosen = [s for s in allsc if not scenes or s.name in scenes]
    refs_ = load_references(chosen, out, log)
    rows = []
    for sc in chosen:
        ref = refs_[sc.name]
        # cross-check: the core's own adaptive integrator at its tightest setting
        xs = solve_quiet(
            sc.scene, Options(integrator="adaptive", rtol=1e-13, tol=WP_TOL, tip_only=True)
        )
        xerr = tip_error(sc, xs.tip_position, ref) if xs.success else math.nan
        log(
            f"[{sc.name}] reference ({sc.ref_kind}) tip {np.array2string(ref, precision=9)}; "
            f"core adaptive 1e-13 differs by {xerr:.2e} (success={xs.success})"
        )
        for jm in jacobian_methods():
            for slack_model in sc.slack_models:
                for method, kw, setting in wp_settings(quick):
                    rows.append(
                        _setting_row(
                            sc, ref, xerr, jm, slack_model, method, kw, setting, repeats, log
                        )
                    )
        rows.append(_default_row(sc, ref, xerr, repeats, log))
    write_csv(os.path.join(out, "work_precision.csv"), rows, WP_COLS)
    plot_work_precision(rows, chosen, os.path.join(out, "work_precision.png"))
    summary = summarize_work_precision(rows)
    with open(os.path.join(out, "work_precision_summary.md"), "w") as fh:
        fh.write(summary)
    log(summary)
    return rows


WP_COLS = [
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
"""The columns of ``work_precision.csv``."""


def _setting_row(sc, ref, xerr, jm, slack_model, method, kw, setting, repeats, log) -> dict:
    """The row of one scene, Jacobian option, slack model and integrator setting; a solve
    that raises is recorded (error NaN), never aborts the table."""
    # the adaptive integrator's residual is only smooth in the unknowns to about
    # its rtol (its step sequence changes with them), so its shooting tolerance
    # follows rtol; fixed-step residuals are smooth to round-off
    tol = WP_TOL if method != "adaptive" else max(WP_TOL, min(1e-10, 1e-3 * setting))
    try:
        opts = Options(
            tol=tol,
            jacobian_method=jm,
            slack_model=slack_model,
            tip_only=True,
            **kw,
        )
        secs, sol = time_solve(sc.scene, opts, repeats)
    except Exception as exc:  # noqa: BLE001 - record, never abort the table
        return dict(
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
    err = (
        tip_error(sc, sol.tip_position, ref) if np.all(np.isfinite(sol.tip_position)) else math.nan
    )
    row = dict(
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
    log(
        f"  {sc.name:12s} {method:8s} {jm:11s} {slack_model:7s} {setting:>8g}: err {err:9.2e} "
        f"t {secs * 1e3:8.3f} ms nit {sol.nit:3d} nfev {sol.nfev:5d} ok={sol.success}"
    )
    return row


def _default_row(sc, ref, xerr, repeats, log) -> dict:
    """The row of what a user gets: default options."""
    secs, sol = time_solve(sc.scene, Options(), repeats)
    err = tip_error(sc, sol.tip_position, ref)
    row = dict(
        scene=sc.name,
        method="default",
        jacobian=Options().jacobian_method,
        slack_model=Options().slack_model,
        setting=0,
        tol=Options().tol,
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
    log(f"  {sc.name:12s} default Options(): err {err:.2e} t {secs * 1e3:.3f} ms")
    return row


def load_references(scenes, out, log=print):
    """Reference tips {name: (3,)} for ``scenes``, cached in ``out/references.json``
    (keyed by the scene's repr, so a changed scene is recomputed). The independent
    ODE references take 10-70 s each in pure Python."""
    cache_path = os.path.join(out, "references.json")
    cache = {}
    # the committed cache (bench/results/references.json of a source checkout) first,
    # then the output directory's own; keys include the scene's repr, so an entry is
    # only used for exactly the scene it was computed for
    # (this file is tendonrod/bench/work_precision.py: three levels below the checkout)
    committed = os.path.join(
        os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
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
