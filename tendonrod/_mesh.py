"""Geometry of a solved robot for drawing and export: the backbone's frames between output
nodes, the tendons' routes mapped through them, and closed triangle meshes of tubes.

Everything here is presentation: it reads a solution's recorded states (world frame, SI)
and builds points and triangles; nothing is solved.

A tube mesh is closed and consistently oriented: every triangle's vertices run
counter-clockwise seen from outside (its normal ``(b - a) x (c - a)`` points outward), the
side made of quads between consecutive rings of ``sides`` vertices, the two ends capped
by a fan around a centre vertex.  A ring's vertices lie at exactly the tube's radius from
the centre line, so the cross-section is the inscribed regular polygon, of area
``(sides / 2) r^2 sin(2 pi / sides)`` (0.16 % short of pi r^2 at 48 sides).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np

from .routing import offsets as tendon_offsets

__all__ = [
    "state_at",
    "tube",
    "backbone_radius",
    "backbone_tube",
    "tendon_route",
    "disk_arcs",
    "Mesh",
]


class Mesh:
    """Vertices (V, 3) [m] and triangles (T, 3) of vertex indices, outward-oriented."""

    __slots__ = ("vertices", "faces")

    def __init__(self, vertices: np.ndarray, faces: np.ndarray):
        self.vertices = vertices
        self.faces = faces

    @staticmethod
    def join(meshes) -> Mesh:
        """One mesh of several (their vertex lists concatenated, faces re-indexed)."""
        meshes = list(meshes)
        if not meshes:
            return Mesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64))
        offs = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
        return Mesh(
            np.concatenate([m.vertices for m in meshes]),
            np.concatenate([m.faces + o for m, o in zip(meshes, offs)]),
        )


def state_at(sol, s) -> tuple[np.ndarray, np.ndarray]:
    """Positions (K, 3) and rotations (K, 3, 3) at arc lengths ``s`` [m], interpolated
    between the output nodes (positions linearly, rotations entry by entry then
    re-orthonormalised by the polar decomposition) -- enough for drawing."""
    s = np.atleast_1d(np.asarray(s, dtype=float))
    ss = np.asarray(sol.s)
    P = np.stack([np.interp(s, ss, np.asarray(sol.position)[:, j]) for j in range(3)], axis=-1)
    Rn = np.asarray(sol.rotation)
    R = np.empty((len(s), 3, 3))
    for i in range(3):
        for j in range(3):
            R[:, i, j] = np.interp(s, ss, Rn[:, i, j])
    u, _, vt = np.linalg.svd(R)
    return P, u @ vt


def _frames_along(P: np.ndarray) -> np.ndarray:
    """Rotation-minimising frames (K, 3, 3) along a polyline P (K, 3): third column the
    tangent, the first two carried by parallel transport (double reflection would be
    finer; a tube's rings only need a twist-free normal)."""
    T = np.gradient(P, axis=0)
    T /= np.linalg.norm(T, axis=1, keepdims=True)
    a = np.array([1.0, 0.0, 0.0]) if abs(T[0, 0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    n = a - T[0] * (a @ T[0])
    n /= np.linalg.norm(n)
    R = np.empty((len(P), 3, 3))
    for k in range(len(P)):
        n = n - T[k] * (n @ T[k])
        n /= np.linalg.norm(n)
        R[k] = np.stack([n, np.cross(T[k], n), T[k]], axis=1)
    return R


def tube(P, R, radius, sides: int = 32, caps: bool = True) -> Mesh:
    """A tube around the centre line ``P`` (K, 3) [m], its ring k in the plane of the
    first two columns of ``R[k]`` (K, 3, 3; None: rotation-minimising frames of ``P``)
    at ``radius`` [m] (a number or one per ring); closed by end caps when ``caps``."""
    P = np.asarray(P, dtype=float)
    if len(P) < 2:
        raise ValueError(f"tube: need at least 2 centre-line points, got {len(P)}")
    if isinstance(sides, bool) or not isinstance(sides, (int, np.integer)) or sides < 3:
        raise ValueError(f"sides must be an int >= 3, got {sides!r}")
    R = _frames_along(P) if R is None else np.asarray(R, dtype=float)
    K = len(P)
    r = np.broadcast_to(np.asarray(radius, dtype=float), (K,))
    th = 2.0 * math.pi * np.arange(sides) / sides
    c, s = np.cos(th), np.sin(th)
    # ring k, vertex j: P_k + r_k (cos th_j d1_k + sin th_j d2_k)
    ring = (
        P[:, None, :]
        + r[:, None, None] * c[None, :, None] * R[:, None, :, 0]
        + r[:, None, None] * s[None, :, None] * R[:, None, :, 1]
    )
    V = ring.reshape(-1, 3)
    k = np.arange(K - 1)[:, None]
    j = np.arange(sides)[None, :]
    jn = (j + 1) % sides
    a, b = k * sides + j, k * sides + jn
    cc, d = (k + 1) * sides + jn, (k + 1) * sides + j
    # (b - a) runs along the ring (e_theta), (c - a) along it and the tangent: their cross
    # product is e_theta x d3 = e_r, outward
    F = np.concatenate(
        [np.stack([a, b, cc], -1).reshape(-1, 3), np.stack([a, cc, d], -1).reshape(-1, 3)]
    )
    if caps:
        i0, i1 = len(V), len(V) + 1
        V = np.concatenate([V, P[:1], P[-1:]])
        jj = np.arange(sides)
        base = np.stack([np.full(sides, i0), (jj + 1) % sides, jj], -1)  # normal -d3
        last = (K - 1) * sides
        tip = np.stack([np.full(sides, i1), last + jj, last + (jj + 1) % sides], -1)  # +d3
        F = np.concatenate([F, base, tip])
    return Mesh(V, F.astype(np.int64))


def backbone_radius(scene, s, side: Literal["left", "right"] = "left") -> np.ndarray:
    """The backbone's radius [m] at arc lengths ``s`` (a segmented rod's per segment, at a
    joint the segment before it, or with ``side="right"`` the one after; a rod without a
    diameter gets L/100, a drawing choice)."""
    rod = scene.robot.rod
    s = np.atleast_1d(np.asarray(s, dtype=float))
    parts = rod.segments or (rod,)
    ends = np.cumsum([p.length for p in parts])
    L = rod.length
    d = np.array([p.diameter if p.diameter is not None else L / 50 for p in parts])
    idx = np.minimum(np.searchsorted(ends, s, side=side), len(parts) - 1)
    return 0.5 * d[idx]


def backbone_tube(sol, sides: int = 32) -> Mesh:
    """The backbone of ``sol`` as a closed tube at its diameter.  A node repeated at a joint
    (the output holds both sides of a breakpoint) becomes the step between the two
    segments' radii (a flat annulus), or is dropped where they agree (a zero-length piece
    would leave degenerate triangles)."""
    scene = sol.scene
    s = np.asarray(sol.s, dtype=float)
    P, R = np.asarray(sol.position), np.asarray(sol.rotation)
    r = backbone_radius(scene, s)
    keep = np.ones(len(s), dtype=bool)
    for k in np.flatnonzero(np.diff(s) == 0.0):
        r_right = backbone_radius(scene, [s[k]], side="right")[0]
        if r_right == r[k]:
            keep[k + 1] = False
        else:
            r[k + 1] = r_right
    return tube(P[keep], R[keep], r[keep], sides)


def tendon_route(sol, scene, i: int, n: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Tendon ``i``'s route: arc lengths (n,) [m] from 0 to its anchor and the points
    (n, 3) [m], world frame: its body-frame offset r(s) mapped through the solved frames."""
    t = scene.robot.tendons[i]
    end = scene.robot.tendon_end(i)
    if n is None:
        n = 60 if t.twist is None and t.path is None else 240
    s = np.linspace(0.0, end, n)
    P, R = state_at(sol, s)
    return s, P + np.einsum("kij,kj->ki", R, tendon_offsets(t, s, end))


def disk_arcs(scene, disks=None) -> np.ndarray:
    """Arc lengths [m] of the spacer disks to draw: ``disks`` given (arc lengths, or a
    count spread evenly over (0, L]), else the scene's point masses (``PointMass.disks``),
    else the knots of a tendon routed disk by disk (``routing.Path.disks``), else none."""
    L = scene.robot.rod.length
    if disks is not None:
        if isinstance(disks, bool):
            raise ValueError(f"disks must be a count or arc lengths [m], got {disks!r}")
        if np.ndim(disks) == 0:
            n = int(disks)
            return np.linspace(0.0, L, n + 1)[1:] if n > 0 else np.zeros(0)
        return np.asarray(disks, dtype=float).ravel()
    from .loads import PointMass

    pm = [ld.s for ld in scene.loads if isinstance(ld, PointMass)]
    if pm:
        return np.asarray(pm, dtype=float)
    for t in scene.robot.tendons:
        if t.path is not None and t.path.kind == "disks":
            return np.asarray(t.path.knots, dtype=float)[1:]
    return np.zeros(0)


def disk_radius(scene) -> float:
    """Drawn radius [m] of a spacer disk: 1.3 times the largest tendon offset (the
    backbone's radius times 4 without tendons)."""
    offs = []
    for t in scene.robot.tendons:
        if t.path is not None:
            offs.append(float(np.max(np.linalg.norm(t.path(t.path.knots), axis=1))))
        else:
            offs.append(max(abs(t.offset), abs(t.offset + t.slope * scene.robot.rod.length)))
    if offs and max(offs) > 0:
        return 1.3 * max(offs)
    return 4.0 * float(backbone_radius(scene, [0.0])[0])


def disks_mesh(sol, scene, arcs, thickness=None, sides: int = 32) -> Mesh:
    """Closed thin cylinders (radius :func:`disk_radius`, ``thickness`` [m], default
    L/150) centred on the backbone at ``arcs``, each normal to it."""
    L = scene.robot.rod.length
    h = L / 150 if thickness is None else float(thickness)
    rad = disk_radius(scene)
    meshes = []
    for s in np.asarray(arcs, dtype=float):
        lo, hi = max(0.0, s - h / 2), min(L, s + h / 2)
        P, R = state_at(sol, [lo, hi])
        if hi - lo < 1e-12:  # a disk at s = 0 or L with no room: along the end frame
            P = np.stack([P[0], P[0] + R[0][:, 2] * h])
            R = np.stack([R[0], R[0]])
        meshes.append(tube(P, R, rad, sides))
    return Mesh.join(meshes)
