"""The paper's figures, as ``python -m tendonrod figures`` writes them: one function per
figure (``make(fast) -> matplotlib Figure``; the numbers worth quoting ride along as
``fig._tendonrod_notes``), their captions, and :func:`figure_registry`, which the
command renders.  The data come from the studies of :mod:`tendonrod.paper`, the
drawing from :mod:`tendonrod.paper.charts` and :mod:`tendonrod.plot`."""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..plot import shapes, tension_vs_load
from . import closed_forms, friction, prototype, robots, studies
from .charts import (
    ALPHA_LABEL,
    TITLE_SIZE,
    compliance_map,
    friction_band,
    friction_hysteresis,
    prototype_deflection,
    prototype_shapes,
    prototype_tension,
    sci,
    sigma_vs_zeta,
    straight_load,
    tip_compliance_vs_alpha,
    tip_sigma_vs_alpha,
    torsion,
)

__all__ = [
    "FigureEntry",
    "figure_registry",
    "paper_figures",
    "fast_mode",
    "CAPTIONS",
    "parse_formats",
    "write_figure",
]


def fast_mode(fast: bool | None = None) -> bool:
    """``fast`` if given, else the environment variable ``TENDONROD_FAST`` (1/true/yes)."""
    if fast is not None:
        return bool(fast)
    return os.environ.get("TENDONROD_FAST", "").strip().lower() in ("1", "true", "yes", "on")


def parse_formats(text: str) -> tuple:
    """``"png,pdf"`` -> ``("png", "pdf")``: the file formats of ``--format`` (each one of
    :data:`tendonrod.plot.FORMATS`, case-insensitive, a leading dot allowed); ValueError
    naming an unknown one."""
    from ..plot import FORMATS

    fmts = tuple(dict.fromkeys(f.strip().lower().lstrip(".") for f in str(text).split(",")))
    bad = [f for f in fmts if f not in FORMATS]
    if bad or not fmts or "" in fmts:
        raise ValueError(
            f"format {text!r}: unknown {', '.join(repr(b) for b in bad) or 'empty entry'}; "
            f"known: {', '.join(FORMATS)} (comma-separated)"
        )
    return fmts


def write_figure(fig, out: str, key: str, formats=("png",), dpi: float = 110.0) -> list:
    """Write ``fig`` as ``out/key.<format>`` for each of ``formats`` (``"png"``, ``"pdf"``,
    ``"svg"``; PNG at ``dpi``) through :func:`tendonrod.plot.savefig`; the file names."""
    from ..plot import savefig

    if isinstance(formats, str):
        formats = parse_formats(formats)
    names = []
    for fmt in formats:
        names.append(f"{key}.{fmt}")
        savefig(fig, os.path.join(out, names[-1]), dpi=dpi)
    return names


def _figure(w=6.4, h=4.8):
    from matplotlib.figure import Figure

    return Figure(figsize=(w, h), layout="constrained")


def fig01(fast=False):
    d = studies.prescribed_comparison(theta=0.0, force=(-0.5, 0.0, 0.0))
    fig = _figure()
    ax = fig.add_subplot()
    shapes(
        {
            "unloaded": d["unloaded"],
            r"tension held ($\tau$ = 0)": d["tension held"],
            "displacement held (q = 0)": d["displacement held"],
        },
        ax=ax,
        styles={"unloaded": {"color": "0.6", "ls": ":"}},
    )
    ax.set_title(
        "0.5 N tip load, Sec. IV-B robot, one inextensible parallel tendon", fontsize=TITLE_SIZE
    )
    tip_t = -d["tension held"][-1, 0]
    tip_d = -d["displacement held"][-1, 0]
    fig._tendonrod_notes = (
        f"Tip deflection: tension held {1e3 * tip_t:.2f} mm (closed form FL^3/3EI "
        f"{1e3 * d['closed tension held']:.2f} mm), displacement held "
        f"{1e3 * tip_d:.2f} mm (closed form FL^3/12EI "
        f"{1e3 * d['closed displacement held']:.2f} mm); tendon tension "
        f"{d['displacement held tension']:.2f} N."
    )
    return fig


def fig03(fast=False):
    fig = _figure()
    sigma_vs_zeta(closed_forms.closed_form_sigma_vs_zeta(slopes=(0.0,)), ax=fig.add_subplot())
    return fig


def fig06(fast=False):
    fig = _figure()
    sigma_vs_zeta(
        closed_forms.closed_form_sigma_vs_zeta(slopes=(0.0, -0.25, -0.5, -0.75, -1.0)),
        ax=fig.add_subplot(),
    )
    return fig


def fig07(fast=False):
    fig = _figure()
    tip_sigma_vs_alpha(closed_forms.closed_form_tip_sigma_vs_alpha(), ax=fig.add_subplot())
    return fig


def fig08(fast=False):
    d = prototype.actuation_tradeoff()
    fig = _figure(10, 4.8)
    a1, a2 = fig.subplots(1, 2)
    shapes(
        {
            f"parallel: $\\tau$ = {d['parallel']['tension']:.1f} N, q = {100 * d['parallel']['q_over_L']:.1f}% L": d[
                "parallel"
            ]["shape"],
            f"converging: $\\tau$ = {d['converging']['tension']:.1f} N, q = {100 * d['converging']['q_over_L']:.1f}% L": d[
                "converging"
            ]["shape"],
        },
        ax=a1,
        scale=1e3,
        unit="mm",
    )
    a1.set_title("actuated to 90 deg, no load", fontsize=TITLE_SIZE)
    cur = {
        f"{r}, q = {1e3 * d[r]['q_loaded']:.1f} mm": d[r]["shape_loaded"]
        for r in ("parallel", "converging")
        if d[r]["shape_loaded"] is not None
    }
    if cur:
        shapes(cur, ax=a2, scale=1e3, unit="mm")
    a2.set_title(f"{d['load']} N tip load, actuated back to the base axis", fontsize=TITLE_SIZE)
    fig._tendonrod_notes = "; ".join(
        f"{r}: tension {d[r]['tension']:.2f} N (closed form eqs. 37-38: {d[r]['tension_closed_form']:.2f} N), "
        f"displacement {100 * d[r]['q_over_L']:.2f}% of L"
        for r in ("parallel", "converging")
    )
    return fig


def fig10(fast=False):
    d = studies.straight_load_sweep(loads=np.linspace(0.0, 3.0, 11 if fast else 31))
    fig = _figure()
    straight_load(d, ax=fig.add_subplot())
    c = d["converging"]
    fig._tendonrod_notes = (
        f"At F L^2/EI = {d['F_nd'][-1]:g}: Cosserat tip deflection / L = "
        + ", ".join(
            f"{k} {d[k]['cosserat'][-1]:.4g} (closed form {d[k]['closed'][-1]:.4g})"
            for k in ("no tendon", "parallel", "converging")
        )
        + f"; with the inextensible converging tendon the tip stays put even at "
        f"large loads (largest |deflection| {np.nanmax(np.abs(c['cosserat'])):.1e} L)."
    )
    return fig


def fig11(fast=False):
    fig = _figure(13, 4.6)
    a1 = fig.add_subplot(1, 3, 1)
    a2 = fig.add_subplot(1, 3, 2)
    a3 = fig.add_subplot(1, 3, 3)
    notes = []
    for ax, f, name in (
        (a1, (-0.5, 0.0, 0.0), "transverse"),
        (a2, (0.0, 0.0, -0.5), "vertical"),
    ):
        d = studies.prescribed_comparison(theta=math.pi / 2, force=f)
        shapes(
            {
                "unloaded": d["unloaded"],
                "tension held": d["tension held"],
                "displacement held": d["displacement held"],
            },
            ax=ax,
            styles={"unloaded": {"color": "0.6", "ls": ":"}},
            scale=1e3,
            unit="mm",
        )
        ax.set_title(f"({'ab'[name == 'vertical']}) {name} 0.5 N tip load", fontsize=TITLE_SIZE)
        notes.append(
            f"{name}: tension with displacement held {d['displacement held tension']:.2f} N"
        )
    d = studies.out_of_plane_comparison()
    cur = {"unloaded": d["unloaded"], "tension held": d["tension held"]}
    for key, P_ in d.items():
        if isinstance(key, tuple) and key[0] == "displacement held":
            cur[f"displacement held, $r^2kL/3EI$ = {key[1]:g}"] = P_
            notes.append(f"out-of-plane, r^2kL/3EI = {key[1]:g}: tip y = {1e3 * P_[-1, 1]:.2f} mm")
    notes.append(f"out-of-plane, tension held: tip y = {1e3 * d['tension held'][-1, 1]:.2f} mm")
    shapes(
        cur,
        ax=a3,
        plane="xy",
        scale=1e3,
        unit="mm",
        styles={"unloaded": {"color": "0.6", "ls": ":"}},
    )
    a3.set_aspect("auto")
    a3.set_title("(c) three tendons, out-of-plane 0.5 N (top view)", fontsize=TITLE_SIZE)
    fig._tendonrod_notes = "; ".join(notes)
    return fig


def fig12(fast=False):
    d = studies.torsion_paradox(n=9 if fast else 21)
    fig = _figure()
    torsion(d, ax=fig.add_subplot())
    fig._tendonrod_notes = (
        "Twist at M L/GJ = 0.5: "
        + ", ".join(f"alpha = {a:g}: {np.degrees(d[a][-1]):.2f} deg" for a in d["alphas"])
        + f" (rod alone {np.degrees(d['M_nd'][-1]):.2f} deg)."
    )
    return fig


def _compliance_map_figure(direction):
    cache = {}

    def f(fast=False):
        if fast not in cache:
            zeta = np.linspace(0.1, 1.0, 5 if fast else 19)
            cache[fast] = studies.compliance_map(zeta=zeta)
        fig = _figure()
        d = cache[fast]
        compliance_map(d, direction, ax=fig.add_subplot())
        fig.axes[0].set_title(
            f"actuated to 90 deg, {ALPHA_LABEL} = {sci(robots.ALPHA_PAPER)}", fontsize=TITLE_SIZE
        )
        fig._tendonrod_notes = (
            "Tip sigma: "
            + "; ".join(
                f"{k[0]}, {k[1]}: {v[-1]:.4g}"
                for k, v in d.items()
                if isinstance(k, tuple) and len(k) == 3 and k[2] == direction
            )
            + "."
        )
        return fig

    return f


def fig16(fast=False):
    d = studies.tip_compliance_vs_alpha(alphas=np.logspace(-1, 4, 6 if fast else 21))
    fig = _figure()
    tip_compliance_vs_alpha(d, ax=fig.add_subplot())
    fig.axes[0].set_title("tip compliance, actuated to 90 deg", fontsize=TITLE_SIZE)
    notes = []
    for dname in robots.DIRECTIONS:
        better = d[("converging", dname)] < d[("parallel", dname)]
        notes.append(
            f"{dname}: converging stiffer "
            + (
                "at every alpha on the grid"
                if better.all()
                else f"from alpha = {d['alpha'][np.argmax(better)]:.3g} on the grid"
                if better.any()
                else "nowhere"
            )
        )
    fig._tendonrod_notes = (
        "; ".join(notes) + " (the paper: transverse always, axial above about 15)."
    )
    return fig


def _slack_figure(opposing):
    def f(fast=False):
        d = studies.slack_study(opposing=opposing, n=11 if fast else 41)
        fig = _figure(10, 4.4)
        a1, a2 = fig.subplots(1, 2)
        labels = ["tendon at +x", "tendon at -x"]
        tension_vs_load(
            d["F"],
            d["locked"]["tension"],
            ax=a1,
            labels=labels[: d["locked"]["tension"].shape[1]],
        )
        a1.set_title("displacement held", fontsize=TITLE_SIZE)
        for key, ls in (("locked", "-"), ("held", "--")):
            td = d[key]["tip_displacement"]
            a2.plot(
                d["F"],
                1e3 * np.linalg.norm(td, axis=1),
                ls=ls,
                marker=".",
                label=f"|tip displacement|, {'displacement' if key == 'locked' else 'tension'} held",
            )
        ax3 = a2.twinx()
        ax3.plot(
            d["F"],
            np.degrees(d["locked"]["tip_angle"]),
            "k:",
            label="tip angle (displacement held)",
        )
        ax3.set_ylabel("tip angle [deg]")
        lo, hi = ax3.get_ylim()
        if hi - lo < 10.0:  # a held angle: do not magnify round-off
            mid = 0.5 * (hi + lo)
            ax3.set_ylim(mid - 5.0, mid + 5.0)
        ok = d["locked"]["success"]
        if not ok.all():
            # the displacement-held curves stop where the locked planar equilibrium
            # buckles out of plane (unstable, see studies.slack_study): say so
            F_end = float(d["F"][np.flatnonzero(ok)[-1]])
            for ax in (a1, a2):
                ax.axvline(F_end, color="0.5", ls=":", lw=1)
            a1.annotate(
                f"beyond {F_end:.2g} N the locked\nrobot buckles out of plane",
                xy=(F_end, 0.5),
                xycoords=("data", "axes fraction"),
                xytext=(-4, 0),
                textcoords="offset points",
                ha="right",
                fontsize="small",
                color="0.3",
            )
        a2.set_xlabel("tip load F [N] (vertical, downwards)")
        a2.set_ylabel("tip displacement [mm]")
        a2.legend(fontsize="x-small", loc="upper left")
        ax3.legend(fontsize="x-small", loc="lower right")
        fig._tendonrod_notes = (
            f"Load at which the first tendon goes slack: {d['F_slack']:.3g} N."
            if math.isfinite(d["F_slack"])
            else "No tendon went slack in the load range."
        )
        return fig

    return f


def _prototype_figure(routing):
    def f(fast=False):
        fig = _figure()
        prototype_deflection(prototype.prototype_curves(routing), ax=fig.add_subplot())
        return fig

    return f


def fig22(fast=False):
    fig = _figure()
    prototype_tension(
        [prototype.prototype_curves("parallel"), prototype.prototype_curves("converging")],
        ax=fig.add_subplot(),
    )
    return fig


def fig23(fast=False):
    fig = _figure(11, 4.4)
    a1, a2 = fig.subplots(1, 2, sharey=True)
    prototype_shapes(prototype.prototype_shapes("parallel"), ax=a1)
    prototype_shapes(prototype.prototype_shapes("converging"), ax=a2)
    return fig


def _band_note(d) -> str:
    """The deflections at the largest load and the band widths, relative to mu = 0."""
    free = d[0.0]["none"]["deflection"][-1]
    parts = [f"{np.degrees(d['theta']):.0f} deg: frictionless {1e3 * free:.2f} mm"]
    for mu in d["frictions"]:
        di, do = d[mu]["in"]["deflection"][-1], d[mu]["out"]["deflection"][-1]
        parts.append(
            f"mu = {mu:g}: in {1e3 * di:.2f}, out {1e3 * do:.2f} mm "
            f"(band {100 * (di - do) / free:.1f}% of frictionless)"
        )
    return ", ".join(parts)


def fig25(fast=False):
    study = friction.axial_load_study()
    fig = _figure(11, 4.6)
    axes = fig.subplots(1, 2)
    for ax, d in zip(axes, study.values()):
        friction_band(d, ax=ax)
    F = next(iter(study.values()))["forces"][-1]
    fig._tendonrod_notes = f"Tip deflection along the load at {F:g} N: " + "; ".join(
        _band_note(d) for d in study.values()
    )
    return fig


def fig25_hysteresis(fast=False):
    d = friction.actuation_hysteresis(n=11 if fast else 31)
    fig = _figure(15, 4.6)
    a1, a2, a3 = fig.subplots(1, 3)
    friction_hysteresis(d, "theta", relative=True, ax=a1)
    friction_hysteresis(d, "tension", ax=a2)
    friction_hysteresis(d, "tip_x", relative=True, ax=a3)
    a1.set_title("tip angle: q fixes it but for the tendon's stretch", fontsize=TITLE_SIZE)
    a2.set_title("actuator tension", fontsize=TITLE_SIZE)
    a3.set_title("tip position: friction moves the bending along s", fontsize=TITLE_SIZE)
    notes = []
    for mu in d["frictions"]:
        b = d[mu]
        notes.append(
            f"mu = {mu:g}: tip angle {np.degrees(b['in']['theta'][-1]):.2f} / "
            f"{np.degrees(b['out']['theta'][-1]):.2f} deg, tip x "
            f"{1e3 * b['in']['tip'][-1, 0]:.1f} / {1e3 * b['out']['tip'][-1, 0]:.1f} mm, actuator tension "
            f"{b['in']['tension'][-1]:.2f} / {b['out']['tension'][-1]:.2f} N"
        )
    free = d[0.0]["none"]
    fig._tendonrod_notes = (
        f"At q = {1e3 * d['q'][-1]:.2f} mm, pulling / releasing: "
        + "; ".join(notes)
        + f" (frictionless {np.degrees(free['theta'][-1]):.2f} deg, "
        f"{1e3 * free['tip'][-1, 0]:.1f} mm, {free['tension'][-1]:.2f} N)."
    )
    return fig


CAPTIONS = {
    "fig01": (
        "Fig. 1: prescribed displacement vs prescribed tension. Straight robot of Sec. IV-B "
        "(Kirchhoff, L = 0.1 m, d = 1.04 mm, one inextensible parallel tendon at 10 mm), 0.5 N "
        "transverse tip load: with the tension held (here 0) the robot deflects as a plain "
        "cantilever, with the tendon displacement held it deflects about a quarter as much "
        "(eq. 12). Cosserat model."
    ),
    "fig03": (
        "Fig. 3: nondimensional compliance at the loaded point against load location, "
        "no tendon (eq. 10 with k = 0) and one inextensible parallel tendon (eq. 11). Closed form."
    ),
    "fig06": (
        "Fig. 6: the same for sloped inextensible tendons, a L / b from 0 (parallel) to -1 "
        "(converging, zero tip compliance, eqs. 29, 33). Closed form."
    ),
    "fig07": (
        "Fig. 7: tip compliance against nondimensional tendon stiffness for parallel (eq. 9) "
        "and converging (eq. 32) routing. Closed form."
    ),
    "fig08": (
        "Fig. 8: actuation trade-off on the Sec. V prototypes (calibrated EI, k): shapes at a "
        "90 deg tip angle (constant vs linearly varying curvature) with the tension and tendon "
        "displacement needed, and the shapes under a 0.9 N tip load actuated back until the tip "
        "is on the base axis. Cosserat model."
    ),
    "fig10": (
        "Fig. 10: closed forms against the Cosserat model for the initially straight robot "
        "(Sec. IV-B) under a growing transverse tip load, tendon locked at q = 0."
    ),
    "fig11": (
        "Fig. 11: robot of Sec. IV-B actuated to 90 deg, prescribed displacement vs prescribed "
        "tension: (a) transverse and (b) vertical in-plane 0.5 N tip loads, one inextensible "
        "tendon; (c) three stretchable tendons, out-of-plane 0.5 N tip load, r^2kL/3EI = 50 and "
        "5e4. Cosserat model."
    ),
    "fig12": (
        "Fig. 12: torsion paradox. Straight robot of Sec. IV-B, three parallel tendons locked "
        "at q = 0, pure twisting moment at the tip; the curve stiffens with tendon stiffness but "
        "its slope at zero stays GJ/L. Cosserat model."
    ),
    "fig13": (
        "Fig. 13: compliance at a loaded point for transverse (horizontal, in-plane) loads, "
        "robot of Sec. IV-B actuated to 90 deg, one tendon, r^2kL/EI = 8.29e6; displacement "
        "held (solid) and tension held (dashed). Cosserat model, linearised (small loads)."
    ),
    "fig14": "Fig. 14: the same for axial (vertical, in-plane) loads.",
    "fig15": "Fig. 15: the same for out-of-plane loads.",
    "fig16": (
        "Fig. 16: tip compliance against nondimensional tendon stiffness, actuated to 90 deg, "
        "parallel and converging, three load directions (Cosserat, locked actuator), with the "
        "straight-robot closed forms of Fig. 7 dotted."
    ),
    "fig17": (
        "Fig. 17: robot of Figs. 17-18 (L = 0.2 m, d = 0.8 mm) with one inextensible tendon, "
        "actuated to 90 deg and locked, under a growing downward tip load: the tension falls to "
        "zero, the tendon goes slack, and the tip then rotates. Cosserat model."
    ),
    "fig18": (
        "Fig. 18: the same with an opposing tendon; both pretensioned (5 N before locking; "
        "r^2kL/EI = 8.29e6 as in the paper: an opposing pair needs some stretch for a defined "
        "tension level) so "
        "neither goes slack and the tip keeps its orientation."
    ),
    "fig20": (
        "Fig. 20: parallel prototype, deflection at the loaded point against load location "
        "(eq. 8 with the calibrated EI = 11.2e3 N mm^2, k = 4.5 N/mm, L = 201 mm, r = 8 mm). "
        "Formulas only: the measured points are not available."
    ),
    "fig21": (
        "Fig. 21: converging prototype (offset 8 -> 1.875 mm), eq. 27 with EI = 11.3e3 N mm^2, "
        "k = 8.55 N/mm. Formulas only."
    ),
    "fig22": (
        "Fig. 22: tendon tension against load location for 20 g and 50 g weights, both "
        "prototypes (eqs. 6 and 25). Formulas only."
    ),
    "fig23": (
        "Fig. 23: loaded shapes of both prototypes for the last four load locations at 0.2 N "
        "and 0.5 N (closed-form tangent angle integrated). Formulas only."
    ),
    "fig25": (
        "Fig. 25 with channel friction: the parallel prototype (Sec. V, EA = k L) pulled to "
        "30 and 60 deg (tendon sliding in), actuator locked, loaded down the base axis at "
        "0-0.5 N. Per Coulomb coefficient mu the band between the tendon slid fully in and "
        "fully out (the bounds static friction allows), beside the frictionless model; "
        "deflection from the actuated state. Cosserat model."
    ),
    "fig25_hysteresis": (
        "Actuation hysteresis of the parallel prototype, unloaded: tip angle (minus the "
        "frictionless one), actuator tension and tip x position (minus the frictionless one) "
        "against tendon displacement, pulling (sliding in) and releasing (sliding out) for "
        "several mu, the frictionless curve between them. Cosserat model."
    ),
}
"""Figure key -> caption, in the order the ``figures`` command writes them."""


def paper_figures():
    """[(key, caption, make(fast) -> matplotlib Figure), ...] for the ``figures`` command.
    The makers are built afresh on each call (a compliance-map figure keeps its data
    between its own calls only)."""
    makers = {
        "fig01": fig01,
        "fig03": fig03,
        "fig06": fig06,
        "fig07": fig07,
        "fig08": fig08,
        "fig10": fig10,
        "fig11": fig11,
        "fig12": fig12,
        "fig13": _compliance_map_figure("transverse"),
        "fig14": _compliance_map_figure("axial"),
        "fig15": _compliance_map_figure("out-of-plane"),
        "fig16": fig16,
        "fig17": _slack_figure(False),
        "fig18": _slack_figure(True),
        "fig20": _prototype_figure("parallel"),
        "fig21": _prototype_figure("converging"),
        "fig22": fig22,
        "fig23": fig23,
        "fig25": fig25,
        "fig25_hysteresis": fig25_hysteresis,
    }
    return [(key, caption, makers[key]) for key, caption in CAPTIONS.items()]


@dataclass(frozen=True)
class FigureEntry:
    """A figure of ``python -m tendonrod figures``: ``make(fast) -> matplotlib Figure``."""

    caption: str
    make: Callable


def figure_registry() -> dict:
    """Every figure the ``figures`` command writes, key -> :class:`FigureEntry`."""
    return {k: FigureEntry(c, m) for k, c, m in paper_figures()}
