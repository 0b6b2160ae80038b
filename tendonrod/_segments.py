"""The distance between line segments, vectorised (the geometry of the plausibility
rule ``self-intersection``)."""

from __future__ import annotations

import numpy as np


def segment_distance(p0, p1, q0, q1) -> np.ndarray:
    """Distances between segments [p0, p1] and [q0, q1] (arrays (M, 3)); degenerate
    segments allowed (Ericson, Real-Time Collision Detection, 5.1.9, vectorised)."""
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    f = np.einsum("ij,ij->i", d2, r)
    c = np.einsum("ij,ij->i", d1, r)
    b = np.einsum("ij,ij->i", d1, d2)
    tiny = 1e-300
    denom = a * e - b * b
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(denom > tiny * np.maximum(a * e, tiny), (b * f - c * e) / denom, 0.0)
        s = np.clip(np.where(a > tiny, s, 0.0), 0.0, 1.0)
        t = np.where(e > tiny, (b * s + f) / e, 0.0)
        # t outside [0, 1] (or a degenerate second segment): clamp t, recompute s for it
        t_c = np.clip(t, 0.0, 1.0)
        redo = (t != t_c) | (e <= tiny)
        s = np.where(redo, np.where(a > tiny, np.clip((b * t_c - c) / a, 0.0, 1.0), 0.0), s)
    t = t_c
    diff = (p0 + d1 * s[:, None]) - (q0 + d2 * t[:, None])
    return np.sqrt(np.einsum("ij,ij->i", diff, diff))
