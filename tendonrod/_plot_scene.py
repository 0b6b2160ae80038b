"""What :func:`tendonrod.plot.robot` draws beside the robot itself: the base and world
frames and gravity's arrow, the point masses (disks as rings, others as dots), a scene
without its masses (to solve the unloaded shape), and equal 3-D axes."""

from __future__ import annotations

import math

import numpy as np

from ._mesh import state_at as _state_at

_AXIS_COLORS = ("tab:red", "tab:green", "tab:blue")


def draw_frame(ax, scene, P, L, planar) -> list:
    """The base frame's axes as arrows (L/8) at the base and gravity's direction as an
    arrow "g" (L/5) beside the robot's top; returns the arrows' end points."""
    robot = scene.robot
    o = np.asarray(robot.base_position, dtype=float)
    R0 = np.asarray(robot.base_rotation, dtype=float)
    arrows = [(o, 0.125 * L * R0[:, j], _AXIS_COLORS[j]) for j in range(3)]
    g = np.asarray(scene.gravity, dtype=float)
    if np.any(g):
        lo, hi = P.min(axis=0), P.max(axis=0)
        u = 0.2 * L * g / np.linalg.norm(g)
        # beside the robot, on the -x side, its head at mid height
        tail = np.array([lo[0] - 0.15 * L, 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])]) - u / 2
        arrows.append((tail, u, "k"))
    ends = []
    for tail, v, c in arrows:
        if planar:
            if abs(v[0]) + abs(v[2]) < 1e-12 * L:  # the y axis seen end-on
                continue
            ax.quiver(
                tail[0], tail[2], v[0], v[2], angles="xy", scale_units="xy", scale=1.0,
                color=c, width=0.004, zorder=3,
            )  # fmt: skip
        else:
            ax.quiver(*tail, *v, color=c, arrow_length_ratio=0.25, lw=1.2)
        ends += [tail, tail + v]
    if np.any(g):
        tail, v, _ = arrows[-1]
        xy = (tail[0], tail[2]) if planar else tuple(tail)
        ax.text(*xy, " g", color="k", fontsize="small", va="bottom")
    return ends


def without_masses(scene):
    """``scene`` without its point masses (the loads that carry a force or moment)."""
    import dataclasses

    from .loads import PointMass

    if not any(isinstance(ld, PointMass) for ld in scene.loads):
        return scene
    kept = [ld for ld in scene.loads if not isinstance(ld, PointMass)]
    return dataclasses.replace(scene, loads=kept)


def draw_masses(sol, scene, draw, planar, rad, alpha):
    """The scene's point masses as brown disks (radius ``rad`` [m]) with a dot at the
    centre line whose area is proportional to the mass."""
    from .loads import PointMass

    pm = [ld for ld in scene.loads if isinstance(ld, PointMass)]
    if not pm:
        return
    mmax = max(ld.mass for ld in pm)
    Ps, Rs = _state_at(sol, [ld.s for ld in pm])
    ang = np.linspace(0.0, 2 * math.pi, 33)
    ring = rad * np.stack([np.cos(ang), np.sin(ang), np.zeros_like(ang)], axis=-1)
    for ld, p, R in zip(pm, Ps, Rs):
        if planar:
            ends = p + np.array([R @ np.array([-rad, 0, 0]), R @ np.array([rad, 0, 0])])
            draw(ends, color="tab:brown", lw=2.5, alpha=alpha)
        else:
            draw(p + ring @ R.T, color="tab:brown", lw=1.5, alpha=alpha)
        size = 6.0 * math.sqrt(ld.mass / mmax) if mmax > 0 else 0.0
        if size > 0:
            draw(p[None], color="tab:brown", ls="", marker="o", ms=size, alpha=alpha)


def equal_3d(ax, P, L):
    """Equal scales on the three axes around the backbone, with few, small ticks."""
    from matplotlib.ticker import MaxNLocator

    c = 0.5 * (P.max(axis=0) + P.min(axis=0))
    h = 0.55 * max(float(np.ptp(P, axis=0).max()), 0.2 * L)
    ax.set_xlim(c[0] - h, c[0] + h)
    ax.set_ylim(c[1] - h, c[1] + h)
    ax.set_zlim(c[2] - h, c[2] + h)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(4))
    ax.tick_params(labelsize="small")
