"""The conditions a robot's pretensions must meet (:class:`tendonrod.Robot` checks them on
construction): a balanced set on every stretch between anchors, straight parallel or
sloped routes on a backbone without pretwist, and some axial compliance to hold them."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

#: relative tolerance of the pretensions' moment balance (of sum |tau_p| r)
_BALANCE_RTOL = 1e-9


def check_pretension(rod, tendons: Sequence, ends: Sequence[float]) -> None:
    """ValueError naming the tendon and its pretension where the set of a robot (its rod,
    its tendons and their anchor arc lengths [m]) cannot be defined."""
    pre = [i for i, t in enumerate(tendons) if t.pretension > 0.0]
    if not pre:
        return
    parts = rod.segments or (rod,)
    if any(t.twist is not None or t.path is not None for t in tendons):
        raise ValueError(
            f"Robot.tendons[{pre[0]}].pretension={tendons[pre[0]].pretension!r}: "
            f"pretension with helical or path-routed tendons is not supported"
        )
    if any(p.precurvature[2] != 0.0 for p in parts):
        raise ValueError(
            f"Robot.tendons[{pre[0]}].pretension={tendons[pre[0]].pretension!r}: "
            f"pretension on a pretwisted backbone (precurvature uz != 0) is not supported "
            f"(its turning channels twist the unloaded robot); prescribe tensions or "
            f"displacements"
        )
    # balance on every segment between anchors: sum tau_p r_i(s) = 0 for all s there,
    # i.e. both the offset and the slope moments vanish for the tendons present.
    start = 0.0
    for e in sorted(set(ends)):
        active = [i for i in range(len(tendons)) if ends[i] >= e]
        mb = np.zeros(2)
        ma = np.zeros(2)
        scale = 0.0
        for i in active:
            t = tendons[i]
            d = np.array([math.cos(t.angle), math.sin(t.angle)])
            mb += t.pretension * t.offset * d
            ma += t.pretension * t.slope * e * d
            scale += t.pretension * (t.offset + abs(t.slope) * e)
        if np.hypot(*mb) > _BALANCE_RTOL * scale or np.hypot(*ma) > _BALANCE_RTOL * scale:
            vals = {i: tendons[i].pretension for i in active}
            raise ValueError(
                f"Robot.tendons pretension {vals} is not balanced on s in [{start:g}, {e:g}] m: "
                f"sum of pretension * r_i(s) must vanish there (moment "
                f"{mb.tolist()} N m from offsets, {ma.tolist()} N m from slopes), otherwise "
                f"the 'unloaded' robot is not straight and pretension is not defined"
            )
        start = e
    if rod.kirchhoff:
        rigid = [i for i in pre if math.isinf(tendons[i].EA)]
        if rigid:
            raise ValueError(
                f"Robot.tendons[{rigid[0]}].pretension={tendons[rigid[0]].pretension!r} "
                f"needs axial compliance: an inextensible tendon (EA=inf) on a Kirchhoff "
                f"(inextensible) backbone cannot hold a defined pretension; give the tendon "
                f"a finite EA or use a Cosserat backbone (kirchhoff=False)"
            )
