"""The drawing of :func:`tendonrod.plot.modes`: mode shapes over the equilibrium's centre
line."""

from __future__ import annotations

import numpy as np

_PLANES = {"xz": (0, 2), "yz": (1, 2), "xy": (0, 1)}


def draw(m, ax_of, which, scale, plane: str, **kwargs):
    """Draw the modes ``which`` of ``m`` (see :func:`tendonrod.plot.modes`); ``ax_of``
    makes the Axes (``None`` or ``"3d"`` projection)."""
    if not m.success:
        raise ValueError(f"plot.modes: the modes were not computed ({m.message})")
    if plane not in _PLANES and plane != "3d":
        raise ValueError(f"plot.modes: plane must be 'xz', 'yz', 'xy' or '3d', got {plane!r}")
    idx = range(min(m.n, 3)) if which is None else np.atleast_1d(which).tolist()
    for k in idx:
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 0 <= k < m.n:
            raise ValueError(f"plot.modes: which must hold mode indices 0..{m.n - 1}, got {k!r}")
    p0 = np.asarray(m.position)
    L = float(m.s[-1])
    a = 0.15 * L if scale is None else float(scale)
    ax = ax_of("3d" if plane == "3d" else None)
    cols = (0, 1, 2) if plane == "3d" else _PLANES[plane]
    ax.plot(*(p0[:, c] for c in cols), color="0.5", lw=2, label="equilibrium")
    for j, k in enumerate(idx):
        d = np.asarray(m.shape_position[k])
        f = m.frequencies[k]
        fs = f"{f.real:.4g} Hz" if np.isreal(f) else f"{f.imag:.4g}i Hz"
        color = f"C{j}"
        ax.plot(*((p0 + a * d)[:, c] for c in cols), color=color, label=f"[{k}] {fs}", **kwargs)
        ax.plot(*((p0 - a * d)[:, c] for c in cols), color=color, ls="--", **kwargs)
    names = "xyz"
    if plane == "3d":
        ax.set_xlabel("x [m]"), ax.set_ylabel("y [m]"), ax.set_zlabel("z [m]")
    else:
        ax.set_xlabel(f"{names[cols[0]]} [m]")
        ax.set_ylabel(f"{names[cols[1]]} [m]")
        ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(f"modes, shapes x {a:.3g} m (+/-)")
    ax.legend(fontsize="small")
    return ax
