"""The charts of the benchmark suites (matplotlib, Agg): work-precision, choice of
model, stress outcomes.  Each takes the rows a suite recorded and writes one PNG."""

from __future__ import annotations

import math

import numpy as np

_STYLE = {
    "rk4": ("tab:blue", "o"),
    "rk8": ("tab:red", "s"),
    "adaptive": ("tab:green", "^"),
    "default": ("k", "*"),
}


def _log_ticks(axis, lo, hi):
    """Labels on a log axis that cannot collide: majors only (matplotlib labels the minor
    ticks of an axis spanning under a decade, and they overlap), at 1-2-5 when the axis
    spans under two decades, at every decade otherwise, in plain numbers."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    span = math.log10(hi / lo) if lo > 0 and hi > lo else 0.0
    if span < 2.0:
        axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())


def plot_work_precision(rows, scenes, path):
    """Write the work-precision chart of ``rows`` (one panel per scene) to ``path``."""
    import matplotlib.pyplot as plt

    fig = work_precision_figure(rows, scenes)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def work_precision_figure(rows, scenes):
    """The work-precision chart as a matplotlib Figure (Agg), not saved."""
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
        _log_ticks(ax.xaxis, *ax.get_xlim())
        _log_ticks(ax.yaxis, *ax.get_ylim())
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    # one legend for the two encodings instead of one entry per combination: colour and
    # marker name the method, the line style its Jacobian (dotted: the quadratic slack form)
    from matplotlib.lines import Line2D

    seen = {(r["method"], r["jacobian"], r["slack_model"]) for r in rows}
    methods = [m for m in _STYLE if any(k[0] == m for k in seen)]
    methods += sorted({k[0] for k in seen} - set(methods))
    handles = [
        Line2D(
            [],
            [],
            color=_STYLE.get(m, ("gray", "x"))[0],
            marker=_STYLE.get(m, ("gray", "x"))[1],
            ls="none" if m == "default" else "-",
            ms=5,
            label=m,
        )
        for m in methods
    ]
    jacobians = sorted({k[1] for k in seen if k[0] != "default" and k[2] == "linear"})
    handles += [
        Line2D(
            [],
            [],
            color="0.3",
            ls={"fd": "-", "newton": "--", "hybrid": "-."}.get(j, (0, (1, 3))),
            label=f"Jacobian: {j}",
        )
        for j in jacobians
    ]
    other = sorted({k[2] for k in seen if k[2] != "linear"})
    if other:
        handles.append(Line2D([], [], color="0.3", ls=":", label="slack form: " + ", ".join(other)))
    handles.append(
        Line2D([], [], color="0.3", marker="x", ls="none", ms=6, label="reported failure")
    )
    fig.legend(handles=handles, loc="lower center", ncol=min(6, len(handles)), fontsize=8)
    fig.suptitle(
        "tendonrod work-precision: relative tip error vs run time (x: solve reported failure)",
        fontsize=11,
    )
    fig.tight_layout(rect=(0, 0.05, 1, 0.96))
    return fig


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
