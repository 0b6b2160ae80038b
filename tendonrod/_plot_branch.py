"""The drawing of :func:`tendonrod.plot.path`: a load path's parameter against a tip
displacement, unstable stretches dashed, special points marked."""

from __future__ import annotations

import numpy as np

_AXES = {"x": 0, "y": 1, "z": 2}
_STYLE = {True: "-", False: "--", None: ":"}
_MARK = {"limit": ("o", "limit point"), "bifurcation": ("s", "bifurcation point")}


def displacement_of(p, displacement: str) -> tuple[np.ndarray, str]:
    """The tip displacement [m] along the path (``"x"``, ``"y"``, ``"z"``: the tip
    position's component minus its value at the start; ``"norm"``: the distance from the
    start's tip) and its axis label."""
    pos = np.asarray(p.tip_position, dtype=float)
    if displacement == "norm":
        return np.linalg.norm(pos - pos[0], axis=1), "tip displacement |Δp| [m]"
    if displacement not in _AXES:
        raise ValueError(f"displacement must be 'x', 'y', 'z' or 'norm', got {displacement!r}")
    c = _AXES[displacement]
    return pos[:, c] - pos[0, c], f"tip displacement Δ{displacement} [m]"


def draw(p, ax, displacement: str, scale: float, ylabel, color, **kwargs):
    """Draw ``p`` on ``ax`` (see :func:`tendonrod.plot.path`)."""
    u, xlabel = displacement_of(p, displacement)
    v = np.asarray(p.value, dtype=float) / scale
    line = None
    seen = set()
    n = len(v)
    i = 0
    while i < n - 1:
        # one stretch per run of one verdict (the verdict of a segment: its end points')
        verdict = p.stable[i + 1] if p.stable[i] is None else p.stable[i]
        j = i + 1
        while j < n - 1 and (p.stable[j + 1] if p.stable[j] is None else p.stable[j]) is verdict:
            j += 1
        if p.branch[j] != p.branch[i]:
            j = i + 1
        label = None
        if verdict not in seen:
            seen.add(verdict)
            label = {True: "stable", False: "unstable", None: "not decided"}[verdict]
        kw = dict(kwargs)
        kw.setdefault("color", color if line is None else line.get_color())
        (line,) = ax.plot(u[i : j + 1], v[i : j + 1], _STYLE[verdict], label=label, **kw)
        i = j
    for sp in p.special_points:
        marker, name = _MARK[sp.kind]
        ax.plot(
            u[sp.index],
            v[sp.index],
            marker,
            mfc="none",
            mec="k",
            ms=8,
            label=name if name not in seen else None,
        )
        seen.add(name)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel if ylabel is not None else p.parameter)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax
