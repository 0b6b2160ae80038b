"""Precurved and segmented backbones: the checks of :class:`~tendonrod.Rod`'s
``precurvature`` and ``segments`` and the core's section rows they compile to.

A segment is a :class:`~tendonrod.Rod` of its own (length, section or rigidities,
precurvature); ``Rod.segmented(parts)`` joins them base first into one backbone whose
joints are breakpoints of the integration, with continuous internal force and moment.
The precurvature ``u* = (ux, uy, uz)`` [1/m] (body frame: bending about body x and y,
twist about z) is the curvature of the unstressed shape, constant on a segment:
``m_b = K_bt (u - u*)``.  Tendon rest lengths, ``q = 0`` and the cold guess refer to that
unstressed, precurved robot.  Python describes; the core (``csrc/tr_backbone.c``) decides.
"""

from __future__ import annotations

import math

import numpy as np

from ._fields import _vec3
from .loads import DistributedLoad

__all__ = ["check_backbone", "pack_sections", "segment_weights", "is_plain"]

# Segment lengths must add up to the rod length to this relative tolerance (round-off of
# a sum of floats).
_SUM_RTOL = 1e-12


def check_backbone(rod) -> tuple:
    """Validate ``rod.precurvature`` and ``rod.segments``; returns them normalised
    ``(precurvature (3 floats), segments (tuple))``, or raises ValueError naming the field."""
    pc = _vec3("Rod", "precurvature", rod.precurvature)
    try:
        segs = tuple(rod.segments)
    except TypeError:
        raise ValueError(f"Rod.segments must be a sequence of Rod, got {rod.segments!r}") from None
    if not segs:
        return pc, segs
    cls = type(rod)
    total = 0.0
    for j, seg in enumerate(segs):
        if not isinstance(seg, cls):
            raise ValueError(f"Rod.segments[{j}] must be a tendonrod.Rod, got {seg!r}")
        if seg.segments:
            raise ValueError(f"Rod.segments[{j}] has segments of its own; give a flat list")
        if seg.kirchhoff != rod.kirchhoff:
            raise ValueError(
                f"Rod.segments[{j}].kirchhoff={seg.kirchhoff!r} differs from the rod's "
                f"kirchhoff={rod.kirchhoff!r}: one backbone model for all segments"
            )
        total += seg.length
    if abs(total - rod.length) > _SUM_RTOL * rod.length:
        raise ValueError(
            f"Rod.segments lengths add up to {total!r} m, but Rod.length = {rod.length!r} m"
        )
    if pc != segs[0].precurvature:
        raise ValueError(
            f"Rod.precurvature={pc!r} must be the base segment's {segs[0].precurvature!r} "
            f"(each segment carries its own)"
        )
    return pc, segs


def segmented(cls, parts):
    """A backbone of the segments ``parts`` (Rod objects, base first): its length is their
    sum, its rigidities and precurvature (which set the solver's scales) the base segment's."""
    try:
        parts = tuple(parts)
    except TypeError:
        raise ValueError(f"Rod.segmented needs a sequence of Rod, got {parts!r}") from None
    if not parts:
        raise ValueError("Rod.segmented needs at least one segment, got none")
    for j, p in enumerate(parts):
        if not isinstance(p, cls):
            raise ValueError(f"Rod.segmented: segments[{j}] must be a tendonrod.Rod, got {p!r}")
    b = parts[0]
    total = math.fsum(p.length for p in parts)
    return cls(
        total,
        EI=b.bending_stiffness,
        GJ=b.torsional_stiffness,
        EA=None if b.kirchhoff else b.axial_stiffness,
        GA=None if b.kirchhoff else b.shear_stiffness,
        kirchhoff=b.kirchhoff,
        precurvature=b.precurvature,
        segments=parts,
    )


def is_plain(rod) -> bool:
    """True for a straight uniform rod (no precurvature, no segments): the core's default."""
    return not rod.segments and rod.precurvature == (0.0, 0.0, 0.0)


def pack_sections(rod) -> np.ndarray | None:
    """The core's section rows (nsec, 8) ``[end [m], EI, GJ [N m^2], EA, GA [N], u* (3)
    [1/m]]`` of ``rod``, or None for a straight uniform rod."""
    if is_plain(rod):
        return None
    parts = rod.segments or (rod,)
    rows = np.empty((len(parts), 8))
    end = 0.0
    for j, p in enumerate(parts):
        end += p.length
        rows[j] = (
            end,
            p.bending_stiffness,
            p.torsional_stiffness,
            p.axial_stiffness,
            p.shear_stiffness,
            *p.precurvature,
        )
    rows[-1, 0] = rod.length
    rows.setflags(write=False)
    return rows


def segment_weights(rod, gravity) -> tuple[DistributedLoad, ...]:
    """The weights ``rho_j A_j g`` [N/m] of the segments with a density, each on its
    arc-length interval (none for an unsegmented rod or without gravity)."""
    if not rod.segments or tuple(gravity) == (0.0, 0.0, 0.0):
        return ()
    out = []
    start = 0.0
    for p in rod.segments:
        w = p.mass_per_length
        end = min(start + p.length, rod.length)
        if w != 0.0:
            out.append(
                DistributedLoad(
                    force=tuple(w * g for g in gravity),
                    start=start,
                    end=end,
                )
            )
        start = end
    return tuple(out)
