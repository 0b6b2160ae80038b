"""Randomized hostile input at every public solver entry point.

tests/test_hostile.py attacks each constructor field and each raw ``_core`` keyword on its
own.  Here whole scenes are drawn -- mostly legal values, with about 3 % of the fields
(rod, tendons, loads, actuation lists, every option, the per-point arrays of
``solve_batch`` and ``sweep``) replaced by an absurd one: NaN, +-inf, 1e300, 5e-324,
-0.0, 2**70 and 10**400, strings, None, lists of the wrong length, NumPy scalars and 0-d
arrays -- and pushed through

  - ``tr.solve(scene, guess=..., options=...)``,
  - ``tr.Problem(scene, options)``: ``solve()``, ``solve(same_structure)``,
    ``solve(other_structure)``, ``solve(guess="cold")``, ``solve(guess=...)``,
    ``compliance(s)`` and a pickled copy's ``solve()``,
  - ``tr.compliance(scene, s=...)``,
  - ``tr.solve_batch(scene, displacement=..., tension=..., forces=..., ...)``,
  - ``tr.sweep`` on its batch path (``loads[0].force[0]``) and its per-point path
    (``robot.rod.length``).

The contract: bad input is refused with a ValueError (or TypeError) that names the
field or parameter (and, for a scalar, shows its value); legal input gets a result, an
honest failure (``success=False`` with a message) or a correct solution
(``check_public_solution`` of test_hostile.py); nothing crashes, hangs, escapes as
another exception type, or returns NaN in a successful result.

The solver calls run in test_hostile's worker subprocess (a crash or a hang is a
:class:`Crash`, not a dead pytest run); the scenes are built in pytest's process, where a
refusal by a constructor is checked to name the field.  A hang is a call that uses more
than CALL_TIMEOUT seconds of CPU time (the worker's guard, whatever the load of the
machine); there is no wall-clock deadline per example (hypothesis ``deadline=None``):
the work of every solve is bounded by its budget, counted by the solver, not by a clock.

Known bugs found by this module are excluded from the random draws (the comment at each
exclusion names the finding), or, where legal input reaches them, recognised by their
exact signature (B13, B14); each has a strict-xfail reproducer at the end of the file,
so that the random tests stay green and the reproducers flip when the bugs are fixed.
"""

import dataclasses
import math
import os
import pickle
import re
import time
import warnings

import numpy as np
import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st
from test_hostile import (
    HANG_SCALE,
    Worker,
    _names_field,
    check_public_solution,
    hostile,
    raised,
)

import tendonrod as tr
from tendonrod.sweeps import (
    OUTCOME_ERROR,
    OUTCOME_NOT_CONVERGED,
    OUTCOME_NOT_RUN,
    OUTCOME_OK,
    STATUS_NONE,
)

# Hostile values are absurd on purpose: the plausibility rules warn of them and solves of
# such scenes may not converge.  Those warnings are expected here (construct() checks
# that none escapes as an exception); the suite turns every other warning into an error.
pytestmark = [
    pytest.mark.filterwarnings("ignore::tendonrod.PlausibilityWarning"),
    pytest.mark.filterwarnings("ignore::tendonrod.ConvergenceWarning"),
]

# --------------------------------------------------------------------------
# Harness: the worker of test_hostile.py, able to import this module
# --------------------------------------------------------------------------

TESTS_DIR = os.path.dirname(os.path.abspath(__file__))

# Hang guard of one worker call [CPU s] (Worker.call multiplies it by HANG_SCALE): far
# above the CPU time of the slowest legal call seen (a spatial compliance with 64
# shooting segments: ~14 s, most of it outside the work budget, in the core's condition
# estimate), so only a hang trips it.  CPU time does not grow with the machine's load.
CALL_TIMEOUT = 60.0


def entry_settings(n):
    """test_hostile's settings (derandomized, no database, no deadline;
    ``TR_HOSTILE_PROFILE=explore`` multiplies the examples by 10) with ``n`` examples."""
    return settings(hostile(n), deadline=None)


class EntryWorker(Worker):
    """test_hostile's worker subprocess with tests/ on its path, so that it can run the
    multi-step scenarios of this module (a Problem must live in the child: its pickle
    re-compiles)."""

    def call(self, name, *args, **kwargs):
        if self.proc is None or self.proc.poll() is not None:
            boot = f"import sys; sys.path.insert(0, {TESTS_DIR!r}); import test_hostile_entry"
            assert super().call("builtins.exec", boot)[0] == "ok"
        kwargs.setdefault("timeout", CALL_TIMEOUT)
        return super().call(name, *args, **kwargs)


@pytest.fixture(scope="module")
def entry_worker():
    w = EntryWorker()
    # start the child (imports NumPy, tendonrod, this module) before any timed example
    assert w.call("math.sqrt", 4.0)[:2] == ("ok", 2.0)
    yield w
    w.close()


# --------------------------------------------------------------------------
# Absurd values
# --------------------------------------------------------------------------

HUGE = 10**400  # beyond every float


def absurd_here(draw):
    """True for about 3 % of the fields.  Hypothesis draws small integers more often
    than a uniform draw would, so the top of the range gives the rate (measured: 3.1 %),
    and shrinking moves toward the legal value."""
    return draw(st.integers(0, 99)) >= 97


def absurd_scalar(v):
    """Absurd stand-ins for the legal scalar ``v`` (some of them legal after all:
    NumPy scalars and 0-d arrays of v, -0.0 where zero is allowed...)."""
    pool = [
        math.nan,
        math.inf,
        -math.inf,
        1e300,
        -1e300,
        5e-324,
        -0.0,
        2**70,
        -(2**70),
        HUGE,
        "abc",
        "0.1",
        "",
        None,
        True,
        1j,
        b"1",
        [v],
        [v, v],
        (),
        {"v": v},
        np.float64(math.nan),
        np.array(math.inf),
        np.int64(3),
    ]
    if isinstance(v, float):
        pool += [np.float64(v), np.float32(v), np.array(v), np.array([v])]
    return st.sampled_from(pool)


def absurd_bool(v):
    return st.sampled_from(["yes", 1, 0, None, 2.5, np.bool_(v), np.array([v]), math.nan])


def absurd_vector(v):
    v = tuple(v)
    return st.sampled_from(
        [
            (math.nan, 0.0, 0.0),
            (0.0, math.inf, 0.0),
            (0.0, 0.0, -math.inf),
            (1e300, 1e300, 1e300),
            (-1e300, 0.0, 0.0),
            (5e-324, 0.0, 0.0),
            (-0.0, -0.0, -0.0),
            (2**70, 0.0, 0.0),
            (HUGE, 0.0, 0.0),
            "abc",
            None,
            3.0,
            v[:2],
            v + (0.0,),
            [v],
            (None, 0.0, 0.0),
            ("1", "2", "3"),
            np.array(v),
            np.asarray(v, dtype=np.float32),
            np.array(v, dtype=complex),
        ]
    )


def absurd_list(v):
    """Absurd stand-ins for a per-tendon actuation list ``v``."""
    return st.sampled_from([list(v)[:-1], list(v) + [0.0], "abc", 0.1, None, np.array(v)])


def inject(draw, legal, pools=None):
    """``(kwargs, absurd)``: the legal keyword arguments with ~3 % of them replaced by
    an absurd value; ``absurd`` maps the replaced names to their values."""
    pools = pools or {}
    kw, bad = dict(legal), {}
    for name, v in legal.items():
        if absurd_here(draw):
            pool = pools.get(name) or (absurd_bool if isinstance(v, bool) else absurd_scalar)
            kw[name] = bad[name] = draw(pool(v))
    return kw, bad


# --------------------------------------------------------------------------
# Checking a refusal
# --------------------------------------------------------------------------

FIELDS = {
    "Rod": {"length", "diameter", "E", "G", "EI", "GJ", "EA", "GA", "kirchhoff"},
    "Tendon": {"offset", "angle", "slope", "EA", "end", "pretension"},
    "Robot": {"rod", "tendons"},
    "PointLoad": {"s", "force", "moment"},
    "DistributedLoad": {"force"},
    "Scene": {"robot", "displacement", "tension", "loads"},
    "Options": {f.name for f in dataclasses.fields(tr.Options)},
}
# "Owner.field" or "Owner.field[i]", or the Scene's "Scene: tendon i has neither/both"
NAMED = re.compile(
    r"\b(Rod|Tendon|Robot|PointLoad|DistributedLoad|Scene|Options)(?:\.(\w+(?:\[\d+\])?)|: (tendon) \d+)"
)


def shows_value(msg, field, value):
    """test_hostile's ``_names_field``, also accepting an int shown as the float it
    stands for (2**70 as 1.1805916207174113e+21)."""
    if _names_field(msg, field, value):
        return True
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) < 2**1000:
        return _names_field(msg, field, float(value))
    return False


def check_refusal(exc, owner, absurd, where="", earlier=frozenset()):
    """``exc``, raised by constructing ``owner`` with the absurd values ``absurd``
    (field -> value; empty: a legal combination was refused), is a ValueError/TypeError
    that names a field of ``owner`` -- an absurd one, one derived from it (whose message
    then quotes the absurd field), or one holding an absurd value that an ``earlier``
    constructor accepted (a PointLoad at s = 1e300 is refused by the Scene) -- and shows
    a scalar's value."""
    assert isinstance(exc, (ValueError, TypeError)), (
        f"{owner}{where}: {type(exc).__name__} escaped: {exc}"
    )
    msg = str(exc)
    named = [(f or t) for o, f, t in NAMED.findall(msg) if o == owner]
    assert named, f"{owner}{where}: the refusal names no field of {owner}: {msg!r}"
    field = named[0]
    base = "displacement" if field == "tendon" else field.split("[")[0]
    assert base in FIELDS[owner], f"{owner}{where}: names no field of {owner}: {msg!r}"
    if absurd:
        quoted = [k for k in absurd if (k in msg if "[" in k else f"{k}=" in msg or f"{k}[" in msg)]
        assert field in absurd or base in absurd or quoted or base in earlier, (
            f"{owner}{where}: refused {absurd!r} but names {field!r}: {msg!r}"
        )
    if field in absurd:
        assert shows_value(msg, field, absurd[field]), (
            f"{owner}{where}: the message does not show {field}={absurd[field]!r}: {msg!r}"
        )


class Refused(Exception):
    """A constructor refused the drawn value (and the refusal has been checked)."""


def construct(owner, ctor, kwargs, absurd, where="", accepted=None):
    """``ctor(**kwargs)``; a refusal is checked and becomes :class:`Refused`; absurd
    values that were accepted are added to ``accepted`` as the words a later refusal by
    the solver may name them by."""
    try:
        obj = ctor(**kwargs)
    except Exception as e:  # noqa: BLE001 - the type is part of what is checked
        check_refusal(e, owner, absurd, where, frozenset(accepted or ()))
        event(f"refused by {owner}")
        raise Refused(owner) from None
    if accepted is not None and absurd:
        accepted |= {k.split("[")[0] for k in absurd} | OWNER_WORDS.get(owner, set())
        if owner == "Rod" and absurd.keys() & {"diameter", "E", "G"}:
            accepted |= {"EI", "GJ", "EA", "GA"}  # derived from the section
    return obj


# How the core's own refusals (tendonrod._core) refer to what an owner holds.
OWNER_WORDS = {
    "Rod": {"rod", "L", "EI", "GJ", "EA", "GA"},
    "Tendon": {"tendon", "tendons"},
    "PointLoad": {"load", "loads"},
    "DistributedLoad": {"dist", "distributed"},
}


def check_accepted(obj):
    """An accepted dataclass holds plain, non-NaN floats (a NaN, string or array that
    slipped through would reach the solver as garbage)."""
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if f.name in ("force", "moment"):
            assert len(v) == 3 and all(type(x) is float and math.isfinite(x) for x in v), obj
        elif isinstance(v, (float, int)) and not isinstance(v, bool):
            assert type(v) is float and not math.isnan(v), (f.name, v, obj)


# --------------------------------------------------------------------------
# Scenes
# --------------------------------------------------------------------------


@st.composite
def scene_specs(draw, point_load_first=False, max_tendons=3):
    """The constructor arguments of a small scene (<= 3 tendons, <= 2 loads) sized so
    that its legal values bend the rod by up to ~2 rad, with ~3 % of every field absurd."""
    L = draw(st.sampled_from([0.2, 0.05, 0.5, 1.0]))
    kirchhoff = draw(st.booleans())
    if draw(st.booleans()):  # a round section
        d = draw(st.sampled_from([0.8e-3, 0.5e-3, 1.5e-3]))
        E = draw(st.sampled_from([207e9, 60e9, 3e9]))
        EI = E * math.pi * d**4 / 64
        rod = dict(length=L, diameter=d, E=E, G=E / 2.6, EI=None, GJ=None, EA=None, GA=None)
    else:  # explicit rigidities
        EI = draw(st.sampled_from([4e-3, 1e-4, 0.05]))
        # inf (rigid) only on a Kirchhoff rod: finding B12
        EA = draw(st.sampled_from([2e7 * EI] + [math.inf] * kirchhoff))
        GA = draw(st.sampled_from([8e6 * EI] + [math.inf] * kirchhoff))
        rod = dict(length=L, diameter=None, E=None, G=None, EI=EI, GJ=0.77 * EI, EA=EA, GA=GA)
    rod["kirchhoff"] = kirchhoff
    spec = {"L": L, "EI": EI, "rod": inject(draw, rod)}

    nt = draw(st.integers(0, max_tendons))
    symmetric = draw(st.booleans())
    b = L * draw(st.sampled_from([0.05, 0.025, 0.1]))
    slope = -b / L * draw(st.sampled_from([0.0, 0.0, 0.5, 1.0]))
    EA_t = draw(st.sampled_from([math.inf, math.inf, 2e4, 1e6]))
    end = draw(st.sampled_from([None, None, 0.5 * L, 0.75 * L]))
    phase = draw(st.sampled_from([0.0, 0.0, 0.3]))
    pre = 0.0
    if symmetric and nt >= 2 and (math.isfinite(EA_t) or not kirchhoff):
        pre = draw(st.sampled_from([0.0, 0.5, 2.0]))  # balanced: equal, evenly spaced
    tendons = []
    for i in range(nt):
        if symmetric:
            t = dict(offset=b, angle=phase + 2 * math.pi * i / nt, slope=slope, EA=EA_t, end=end)
        else:
            bi = L * draw(st.sampled_from([0.05, 0.025, 0.1, 0.0]))
            t = dict(
                offset=bi,
                angle=draw(
                    st.one_of(
                        st.sampled_from([0.0, math.pi, math.pi / 2]), st.floats(-math.pi, math.pi)
                    )
                ),
                slope=-bi / L * draw(st.sampled_from([0.0, 0.5, 1.0])),
                EA=draw(st.sampled_from([math.inf, 2e4, 1e6])),
                end=draw(st.sampled_from([None, 0.5 * L, L])),
            )
        t["pretension"] = pre
        tendons.append(inject(draw, t))
    spec["tendons"] = tendons
    spec["tendons_absurd"] = (
        (draw(st.sampled_from([None, 5, [None], ["x"], "abc"])),) if absurd_here(draw) else None
    )

    disp, tens = [], []
    for kw, _ in tendons:
        r = max(kw["offset"] if isinstance(kw["offset"], float) else b, 0.01 * L)
        if draw(st.booleans()):
            # bending angle ~ q / r
            th = draw(st.one_of(st.sampled_from([0.0, 0.5, -0.5]), st.floats(-1.0, 2.0)))
            disp.append(r * th)
            tens.append(None)
        else:
            # bending angle ~ tau r L / EI
            th = draw(st.one_of(st.sampled_from([0.0, 1.0]), st.floats(0.0, 2.0)))
            disp.append(None)
            tens.append(EI / (r * L) * th)
    act, act_bad = {}, {}
    for name, vals in (("displacement", disp), ("tension", tens)):
        vals = list(vals)
        for i, v in enumerate(vals):
            if v is not None and absurd_here(draw):
                vals[i] = act_bad[f"{name}[{i}]"] = draw(absurd_scalar(v))
        if nt and absurd_here(draw):
            vals = act_bad[name] = draw(absurd_list(vals))
        act[name] = vals if nt else draw(st.sampled_from([None, None, []]))

    planar = draw(st.booleans())

    def vec(scale, moment=False):
        v = draw(st.lists(st.one_of(st.just(0.0), st.floats(-1.0, 1.0)), min_size=3, max_size=3))
        if planar:  # x-z plane: forces without y, moments about y only
            v = [0.0, v[1], 0.0] if moment else [v[0], 0.0, v[2]]
        return tuple(scale * x for x in v)

    loads = []
    npl = draw(st.integers(1 if point_load_first else 0, 2))
    vpools = {"force": absurd_vector, "moment": absurd_vector}
    for _ in range(npl):
        s = L * draw(st.sampled_from([1.0, 1.0, 0.5, 0.25, 0.0]))
        m = vec(0.3 * EI / L, moment=True) if draw(st.booleans()) else (0.0, 0.0, 0.0)
        loads.append(
            ("PointLoad", *inject(draw, dict(s=s, force=vec(EI / L**2), moment=m), vpools))
        )
    if npl < 2 and draw(st.booleans()):
        loads.append(("DistributedLoad", *inject(draw, dict(force=vec(EI / L**3)), vpools)))
    spec["loads"] = loads
    if absurd_here(draw):
        act["loads"] = act_bad["loads"] = draw(
            st.sampled_from([5, "x", [None], [tr.Tendon(offset=0.01)]])
        )
    spec["scene"] = (act, act_bad)
    return spec


def build_scene(spec):
    """``(scene, accepted)``: the Scene of ``spec`` and the names of the absurd values
    its constructors accepted (a refusal by the solver must name one of them);
    :class:`Refused` (after checking the refusal) when a constructor refuses it."""
    acc = set()
    rod = construct("Rod", tr.Rod, *spec["rod"], accepted=acc)
    check_accepted(rod)
    tendons = []
    for i, (kw, bad) in enumerate(spec["tendons"]):
        tendons.append(construct("Tendon", tr.Tendon, kw, bad, f" (tendon {i})", acc))
        check_accepted(tendons[-1])
    if spec["tendons_absurd"] is not None:
        (t,) = spec["tendons_absurd"]
        robot = construct("Robot", tr.Robot, {"rod": rod, "tendons": t}, {"tendons": t})
    else:
        robot = construct("Robot", tr.Robot, {"rod": rod, "tendons": tendons}, {})
    act, bad = spec["scene"]
    kw = dict(act)
    if "loads" not in kw:
        loads = []
        for cls, lkw, lbad in spec["loads"]:
            loads.append(construct(cls, getattr(tr, cls), lkw, lbad, accepted=acc))
            check_accepted(loads[-1])
        kw["loads"] = loads
    scene = construct("Scene", lambda **k: tr.Scene(robot, **k), kw, bad, accepted=acc)
    return scene, acc


# --------------------------------------------------------------------------
# Options
# --------------------------------------------------------------------------

DEFAULT_MAX_WORK = tr.Options().max_work


def absurd_nodes(v):
    return st.sampled_from(
        [
            0,
            1,
            -1,
            10**6 + 1,
            2**70,
            2.5,
            math.nan,
            [math.nan],
            [0.5, 0.1],
            [],
            [-0.1],
            [0.0, 1e300],
        ]
        + ["abc", None, np.array(3), [[0.0, 0.01]], np.zeros((2, 2))]
    )


def absurd_choice(v):
    return st.sampled_from(["RK8", "rk4 ", "", "sensitivity", None, 3, b"fd", [v], np.array([v])])


def absurd_int(v):
    return st.sampled_from(
        [
            -1,
            0,
            2**31,
            2**70,
            HUGE,
            2.5,
            float(v),
            "3",
            None,
            True,
            math.nan,
            np.int64(v),
            np.array(v),
        ]
    )


def absurd_real(v):
    return st.sampled_from(
        [
            math.nan,
            math.inf,
            -1.0,
            0.0,
            -0.0,
            5e-324,
            1e300,
            2.0,
            "1e-8",
            None,
            True,
            np.float64(v),
            np.array(v),
            [v],
            2**70,  # not 10**400: finding B11 (OverflowError)
        ]
    )


OPTION_POOLS = {
    "integrator": absurd_choice,
    "jacobian_method": absurd_choice,
    "slack_model": absurd_choice,
    "nodes": absurd_nodes,
    **{
        k: absurd_int
        for k in ("steps", "max_iter", "max_nfev", "max_continuation", "shooting_segments")
    },
    **{k: absurd_real for k in ("rtol", "tol", "max_work", "max_time")},
}


@st.composite
def options_specs(draw, max_segments=64):
    """``(form, kwargs, absurd)``: mostly-legal values of every Options field (a small
    work budget for speed, the default one in 1 example of 8), ~3 % absurd, passed as
    an Options (mostly), a dict or None; at ~3 % the options argument itself is absurd.

    ``max_segments``: the largest shooting_segments drawn.  A spatial solve with 64
    segments costs ~1 s even when it converges in 0 iterations (work outside the budget,
    as in finding B7), so the tests that make up to 8 solves per example draw at most 16
    to keep the module's run time down."""
    if absurd_here(draw):
        bad = draw(st.sampled_from(["fast", 3, {"nonsense": 1}, {"steps": -1}, tr.Rod]))
        return ("absurd", bad, {"options": bad})
    nodes = draw(
        st.one_of(
            st.sampled_from([101, 2, 9]),
            # arc lengths in [0, L]; not 10**6 nodes (the legal maximum; slow to record)
            # (fractions of L: build_options scales them)
            st.lists(st.floats(0.0, 1.0), min_size=1, max_size=5).map(sorted),
        )
    )
    legal = dict(
        integrator=draw(st.sampled_from(["rk8", "rk8", "rk4", "adaptive"])),
        # fixed step counts fine enough for check_public_solution's 1e-6 balance and
        # orthonormality (rk4 with 8 steps is legal but off by 5e-6, by design)
        steps=draw(st.sampled_from([0, 0, 0, 300, 1000])),
        rtol=draw(st.sampled_from([1e-10, 1e-8, 1e-12])),
        tol=draw(st.sampled_from([1e-10, 1e-10, 1e-8, 1e-12])),
        max_iter=draw(st.sampled_from([50, 50, 8, 1, 500])),
        max_nfev=draw(st.sampled_from([20000, 20000, 50, 1, 10**6])),
        jacobian_method=draw(st.sampled_from(["fd", "fd", "newton", "hybrid"])),
        slack_model=draw(st.sampled_from(["linear", "linear", "squared"])),
        continuation=draw(st.booleans()),
        max_continuation=draw(st.sampled_from([64, 64, 0, 4, 1000])),
        nodes=nodes,
        force_spatial=draw(st.booleans()),
        tip_only=draw(st.booleans()),
        shooting_segments=draw(st.sampled_from([1, 1, 1, 2, 5, max_segments])),
        # 2e6 units ~ 70 ms: a hopeless solve gives up quickly; the default (~0.5 s)
        # in 1 of 8 examples checks that it bounds a hopeless solve as documented
        max_work=draw(st.sampled_from([2e6] * 5 + [DEFAULT_MAX_WORK, 1e4, 1.0])),
        max_time=draw(st.sampled_from([0.0] * 8 + [1e-3, 5e-324])),
    )
    kw, bad = inject(draw, legal, OPTION_POOLS)
    form = draw(st.sampled_from(["Options"] * 6 + ["dict", "none"]))
    return (form, kw, bad)


def build_options(spec, L):
    """``(options argument, Options, refuse, accepted)`` for a rod of length ``L`` (the
    drawn arc-length nodes are fractions of it): ``refuse`` names an absurd options
    argument (the entry point must refuse it), ``accepted`` the absurd fields that
    Options accepted (a later refusal may name them); :class:`Refused` when Options
    refuses the drawn values."""
    form, kw, bad = spec
    if form != "absurd" and isinstance(kw["nodes"], list) and kw["nodes"]:
        if all(type(x) is float for x in kw["nodes"]):
            kw = dict(kw, nodes=[L * x for x in kw["nodes"]])
    if form == "absurd":
        return kw, None, {"options", "nonsense", "steps"}, set()
    if form == "none":
        return None, tr.Options(), set(), set()
    acc = set()
    opts = construct("Options", tr.Options, kw, bad, accepted=acc)
    return (opts if form == "Options" else dict(kw)), opts, set(), acc


# --------------------------------------------------------------------------
# Checking an entry point's outcome
# --------------------------------------------------------------------------


def mentions(msg, names):
    """True when ``msg`` names one of ``names`` as a word (``s`` in "s must be" but
    not in "could not convert string")."""
    return any(re.search(rf"(?<![\w]){re.escape(n)}(?![a-zA-Z_])", msg) for n in names)


def check_call(out, names, where):
    """A raise must be a ValueError/TypeError naming one of ``names`` (the arguments
    that were absurd; empty: nothing was, and a refusal is a bug)."""
    assert out[0] == "raise", out
    assert raised(out, ValueError, TypeError), f"{where}: {out[1][0]} escaped: {out[2]}"
    assert names, f"{where}: legal input refused: {out[1][0]}: {out[2]}"
    assert mentions(out[2], names), (
        f"{where}: the refusal names none of {sorted(names)}: {out[2]!r}"
    )
    event(f"refused: {sorted(names)[0]}")


def check_solution(scene, sol, where):
    """check_public_solution, and no NaN anywhere in a successful result."""
    verdict = check_public_solution(scene, sol, where=where)
    if verdict == "success":
        for name in ("base_state", "unknowns"):
            v = getattr(sol, name)
            assert v is not None and np.all(np.isfinite(v)), f"{where}: success with {name} {v}"
        assert math.isfinite(sol.residual_norm), where
    return verdict


def check_solve_outcome(scene, out, names, where):
    if out[0] == "raise":
        check_call(out, names, where)
        return "refused"
    verdict = check_solution(scene, out[1], where)
    event(f"solve: {verdict}")
    return verdict


# --------------------------------------------------------------------------
# tr.solve
# --------------------------------------------------------------------------

_BASE_SOLUTION = []


def base_solution():
    """A converged Solution of a one-tendon scene (a legal guess of another scene)."""
    if not _BASE_SOLUTION:
        rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
        sc = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), displacement=[0.004])
        _BASE_SOLUTION.append(tr.solve(sc))
    return _BASE_SOLUTION[0]


@st.composite
def guesses(draw):
    """``(kind, absurd?)``: None, "cold", "base" (a Solution of a one-tendon scene),
    "zeros" / "random" (a finite vector of the right length), or an absurd guess."""
    if absurd_here(draw):
        # not [10**400] * k: finding B4 (OverflowError)
        return draw(
            st.sampled_from(["warm", "", 3.0, np.array(1.0), "short", "nan", "long", {"a": 1}])
        ), True
    return draw(st.sampled_from([None, None, "cold", "base", "zeros", "random"])), False


def make_guess(kind, nt, draw_floats):
    n = 6 + 2 * nt
    return (
        {
            "base": base_solution() if kind == "base" else None,
            "zeros": np.zeros(n),
            "random": np.array(draw_floats(n)),
            "short": np.zeros(n - 1),
            "long": np.zeros(n + 1),
            "nan": np.full(n, np.nan),
        }.get(kind, kind)
        if isinstance(kind, str)
        else kind
    )


@entry_settings(400)
@given(spec=scene_specs(), ospec=options_specs(), g=guesses(), data=st.data())
def test_solve_entry(entry_worker, spec, ospec, g, data):
    """tr.solve(scene, guess=..., options=...) on drawn scenes, options and guesses:
    constructors refuse absurd fields by name; the solve refuses an absurd guess or
    options argument by name, and otherwise returns an honest failure or a correct,
    NaN-free solution -- within its CPU-time hang guard, without a crash."""
    try:
        scene, accepted = build_scene(spec)
        arg, _, opt_names, opt_acc = build_options(ospec, scene.robot.rod.length)
    except Refused:
        return
    names = opt_names | accepted | opt_acc
    kind, bad_guess = g
    nt = scene.robot.n_tendons
    guess = make_guess(
        kind,
        nt,
        lambda n: data.draw(st.lists(st.floats(-10.0, 10.0), min_size=n, max_size=n)),
    )
    if bad_guess or (kind == "base" and nt != 1):  # a Solution with another tendon count
        names = names | {"guess"}
    out = entry_worker.call("tendonrod.solve", scene, guess=guess, options=arg)
    check_solve_outcome(scene, out, names, "tr.solve")


# --------------------------------------------------------------------------
# tr.Problem
# --------------------------------------------------------------------------


def problem_scenario(scene, options, same, other, guess, s):
    """In the worker: the life of one Problem.  ``{step: outcome}``, each outcome
    ``("ok", result)`` or ``("raise", [MRO class names], message)``."""
    out = {}

    def step(name, f, *a, **k):
        try:
            out[name] = ("ok", f(*a, **k))
        except Exception as e:  # noqa: BLE001 - reported to the parent
            out[name] = ("raise", [c.__name__ for c in type(e).__mro__], str(e))
        return out[name]

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        made = step("Problem", tr.Problem, scene, options)
        if made[0] == "raise":
            return out
        prob = made[1]
        out["Problem"] = ("ok", None)  # a Problem is not sent back: its pickle recompiles
        first = step("solve()", prob.solve)
        if same is not None:
            step("solve(same)", prob.solve, same)
        if other is not None:
            step("solve(other)", prob.solve, other)
        step("solve(cold)", prob.solve, guess="cold")
        if isinstance(guess, str) and guess == "first":
            guess = first[1] if first[0] == "ok" else None
        step("solve(guess)", prob.solve, guess=guess)
        step("compliance", prob.compliance, s)
        copy = step("pickle", lambda: pickle.loads(pickle.dumps(prob)))
        if copy[0] == "ok":
            c = copy[1]
            out["pickle"] = (
                "ok",
                dict(
                    scene=c.scene == prob.scene,
                    options=c.options == prob.options,
                    cold=c.last_solution is None,
                ),
            )
            step("copy.solve()", c.solve)
    return out


# One change of structure each, with the field the ValueError must name (the first
# structural item of tendonrod.problem._structure that differs).
def _mutations(scene):
    rob, L = scene.robot, scene.robot.rod.length
    rod = rob.rod
    muts = {
        "robot.rod.length": lambda: dataclasses.replace(
            scene, robot=dataclasses.replace(rob, rod=dataclasses.replace(rod, length=1.5 * L))
        ),
        "robot.rod.kirchhoff": lambda: dataclasses.replace(
            scene,
            robot=dataclasses.replace(
                rob, rod=dataclasses.replace(rod, kirchhoff=not rod.kirchhoff)
            ),
        ),
        "robot.tendons (count)": lambda: tr.Scene(
            tr.Robot(rod, list(rob.tendons) + [tr.Tendon(offset=0.05 * L)]),
            displacement=list(scene.displacement) + [0.0],
            tension=list(scene.tension) + [None],
            loads=scene.loads,
        ),
        "loads (number of point loads)": lambda: dataclasses.replace(
            scene, loads=list(scene.loads) + [tr.PointLoad(s=L)]
        ),
    }
    stiff = "EI" if rod.EI is not None else "E"
    muts[f"robot.rod.{stiff}"] = lambda: dataclasses.replace(
        scene,
        robot=dataclasses.replace(
            rob, rod=dataclasses.replace(rod, **{stiff: 2.0 * getattr(rod, stiff)})
        ),
    )
    for i, t in enumerate(rob.tendons[:1]):

        def tendon(**ch):
            ts = list(rob.tendons)
            ts[i] = dataclasses.replace(t, **ch)
            return dataclasses.replace(scene, robot=dataclasses.replace(rob, tendons=ts))

        muts[f"robot.tendons[{i}].angle"] = lambda: tendon(angle=t.angle + 0.3)
        muts[f"robot.tendons[{i}].offset"] = lambda: tendon(offset=2 * t.offset + 0.01 * L)
        muts[f"robot.tendons[{i}].EA"] = lambda: tendon(EA=5e4 if math.isinf(t.EA) else math.inf)
        muts[f"robot.tendons[{i}].end"] = lambda: tendon(end=0.6 * rob.tendon_end(i))
        d, te = list(scene.displacement), list(scene.tension)
        d[i], te[i] = (None, 0.0) if d[i] is not None else (0.0, None)
        muts[f"displacement[{i}] (control kind)"] = lambda: dataclasses.replace(
            scene, displacement=d, tension=te
        )
    pls = scene.point_loads
    if pls:
        p0 = pls[0]
        moved = dataclasses.replace(p0, s=0.5 * p0.s if p0.s > 0 else 0.5 * L)
        muts["point load 0 position s"] = lambda: dataclasses.replace(
            scene, loads=[moved if ld is p0 else ld for ld in scene.loads]
        )
    return muts


def same_structure(draw, scene):
    """``(scene with other values only, accepted absurd names)``: actuation redrawn
    (~3 % absurd), loads and pretensions scaled by nonzero factors (a zero stays zero:
    planarity is kept); None for the scene when the Scene refuses it."""
    rob = scene.robot
    c = draw(st.sampled_from([0.5, 1.5, -1.0, 2.0]))
    cp = draw(st.sampled_from([1.0, 0.5, 3.0]))
    disp, tens, bad = list(scene.displacement), list(scene.tension), {}
    for i, t in enumerate(rob.tendons):
        r = max(t.offset, 0.01 * rob.rod.length)
        if disp[i] is not None:
            disp[i] = r * draw(st.floats(-1.0, 2.0))
            if absurd_here(draw):
                disp[i] = bad[f"displacement[{i}]"] = draw(absurd_scalar(disp[i]))
        else:
            tens[i] = tens[i] * draw(st.floats(0.0, 2.0))
            if absurd_here(draw):
                tens[i] = bad[f"tension[{i}]"] = draw(absurd_scalar(tens[i]))
    loads = []
    for ld in scene.loads:
        if isinstance(ld, tr.PointLoad):
            loads.append(
                tr.PointLoad(
                    s=ld.s, force=[c * x for x in ld.force], moment=[c * x for x in ld.moment]
                )
            )
        else:
            loads.append(tr.DistributedLoad(force=[c * x for x in ld.force]))
    robot = tr.Robot(
        rob.rod, [dataclasses.replace(t, pretension=cp * t.pretension) for t in rob.tendons]
    )
    acc = set()
    try:
        same = construct(
            "Scene",
            lambda **k: tr.Scene(robot, **k),
            dict(displacement=disp, tension=tens, loads=loads),
            bad,
            " (same structure)",
            acc,
        )
    except Refused:
        return None, acc
    return same, acc


def absurd_s(L):
    # not strings, complex, lists, arrays or 10**400: findings B1-B3 (tr.compliance and
    # Problem.compliance do not name s, or raise OverflowError)
    return st.sampled_from(
        [
            math.nan,
            math.inf,
            -math.inf,
            -0.0,
            0.0,
            -L,
            2 * L,
            1e300,
            5e-324,
            2**70,
            L * (1 + 1e-13),
            np.float64(L),
        ]
    )


@st.composite
def arc_lengths(draw, L):
    """``(s, absurd?)`` for compliance: None (the tip) mostly, or a point in (0, L]."""
    if absurd_here(draw):
        return draw(absurd_s(L)), True
    return draw(st.one_of(st.none(), st.none(), st.floats(0.05, 1.0).map(lambda f: f * L))), False


def known_b14(out, opts):
    """Finding B14: when the work budget runs out in the linearisation after the solve
    converged, compliance raises a plain RuntimeError carrying the solve's success
    message ("converged in ...") instead of a ConvergenceError."""
    return (
        raised(out, RuntimeError)
        and not raised(out, tr.ConvergenceError)
        and out[2].startswith("converged")
    )


@entry_settings(250)
@given(spec=scene_specs(), ospec=options_specs(max_segments=16), data=st.data())
def test_problem_entry(entry_worker, spec, ospec, data):
    """tr.Problem(scene, options) and everything it offers, in one child: solve()
    (cold), solve(same structure, other values), solve(another structure) -> ValueError
    naming the differing field, solve(guess="cold"), solve(guess=first solution or a
    drawn guess), compliance(s), and a pickled copy (scene and options kept, warm state
    dropped) whose solve() is bitwise the first one."""
    try:
        scene, accepted = build_scene(spec)
        arg, opts, opt_names, opt_acc = build_options(ospec, scene.robot.rod.length)
    except Refused:
        return
    names = opt_names | accepted | opt_acc
    same, same_acc = same_structure(data.draw, scene)
    muts = _mutations(scene)
    which = data.draw(st.sampled_from(sorted(muts)))
    try:
        other = muts[which]()
    except ValueError as e:  # the changed design is itself refused (e.g. pretension)
        owner = NAMED.search(str(e))
        assert owner, str(e)
        check_refusal(e, owner.group(1), {}, f" ({which})")
        other = None
    kind, bad_guess = data.draw(guesses())
    if kind is None:
        kind = "first"
    guess = make_guess(
        kind,
        scene.robot.n_tendons,
        lambda n: data.draw(st.lists(st.floats(-10.0, 10.0), min_size=n, max_size=n)),
    )
    if kind == "base" and scene.robot.n_tendons != 1:
        bad_guess = True
    s, bad_s = data.draw(arc_lengths(scene.robot.rod.length))
    out = entry_worker.call(
        "test_hostile_entry.problem_scenario", scene, arg, same, other, guess, s
    )
    assert out[0] == "ok", out
    res = out[1]
    if res["Problem"][0] == "raise":
        # Options.nodes beyond L is refused when the problem is compiled
        nodes = {"nodes"} if opts is not None and isinstance(opts.nodes, np.ndarray) else set()
        check_call(res["Problem"], names | nodes, "tr.Problem")
        return
    assert not opt_names, f"tr.Problem accepted options={arg!r}"
    checked = {}
    for step, sc, may in (
        ("solve()", scene, set()),
        ("solve(same)", same, same_acc),  # set_values may refuse an absurd value
        ("solve(cold)", scene, set()),
        ("solve(guess)", scene, {"guess"} if bad_guess else set()),
    ):
        if step in res:
            checked[step] = check_solve_outcome(sc, res[step], may, f"Problem.{step}")
    if other is not None:
        o = res["solve(other)"]
        assert raised(o, ValueError), f"Problem.solve(another structure: {which}): {o}"
        assert which in o[2] and "structure" in o[2], (which, o[2])
    # compliance: of the last successful solution; an honest ConvergenceError if its
    # re-solve fails; RuntimeError only when no solve has succeeded yet (documented)
    c = res["compliance"]
    any_success = "success" in checked.values()
    if c[0] == "ok":
        C = np.asarray(c[1])
        assert C.shape == (6, 6) and np.all(np.isfinite(C)), C
        event("compliance: ok")
    elif raised(c, tr.ConvergenceError):
        assert any_success and c[2], c
        event("compliance: ConvergenceError")
    elif raised(c, RuntimeError) and "needs a successful solve" in c[2]:
        # after a success, only finding B13: the C workspace's last solve failed
        last = [
            res[k] for k in ("solve()", "solve(same)", "solve(cold)", "solve(guess)") if k in res
        ]
        last_failed = [o for o in last if o[0] == "ok"][-1][1].success is False
        assert not any_success or (last_failed and "of this Problem" in c[2]), c
        event("compliance: no solution yet" if not any_success else "compliance: B13")
    elif known_b14(c, opts):
        event("compliance: B14")
    else:
        # a legal s that the core cannot probe (within 1e-12 L of the base) is refused
        # naming s too
        check_call(c, {"s"}, f"Problem.compliance({s!r})")
        assert bad_s or "breakpoint" in c[2], c
    # pickling keeps scene and options, drops the warm state; the copy solves like new
    assert res["pickle"] == ("ok", dict(scene=True, options=True, cold=True)), res["pickle"]
    a, b = res["solve()"][1], res["copy.solve()"][1]
    check_solution(scene, b, "unpickled Problem.solve()")
    if opts.max_time == 0.0:  # deterministic: the same cold solve, bit for bit
        assert (a.status, a.success) == (b.status, b.success), (a.message, b.message)
        assert np.array_equal(a.position, b.position, equal_nan=True)
        assert np.array_equal(a.tension, b.tension, equal_nan=True)


# --------------------------------------------------------------------------
# tr.compliance
# --------------------------------------------------------------------------


@entry_settings(200)
@given(spec=scene_specs(), ospec=options_specs(), data=st.data())
def test_compliance_entry(entry_worker, spec, ospec, data):
    """tr.compliance(scene, s=..., options=...): a finite (6, 6) matrix, an honest
    ConvergenceError when the scene does not solve, or a ValueError/TypeError naming
    s (or options) -- never another exception, a crash or a hang."""
    try:
        scene, accepted = build_scene(spec)
        arg, opts, opt_names, opt_acc = build_options(ospec, scene.robot.rod.length)
    except Refused:
        return
    names = opt_names | accepted | opt_acc
    s, bad_s = data.draw(arc_lengths(scene.robot.rod.length))
    out = entry_worker.call("tendonrod.compliance", scene, s=s, options=arg)
    if out[0] == "ok":
        C = np.asarray(out[1])
        assert C.shape == (6, 6) and np.all(np.isfinite(C)), C
        L = scene.robot.rod.length
        assert not opt_names, f"tr.compliance accepted options={arg!r}"
        assert not bad_s or 0.0 < float(s) <= L * (1 + 1e-12), f"tr.compliance accepted s={s!r}"
        event("compliance: ok")
    elif raised(out, tr.ConvergenceError):
        # the scene did not solve, or (a small max_work) the budget ran out while
        # linearising the solved state: both say so
        assert "did not solve" in out[2] or "ran out while linearising" in out[2], out
        event("compliance: ConvergenceError")
    elif known_b14(out, opts):
        event("compliance: B14")
    else:
        check_call(out, names | {"s"}, f"tr.compliance(s={s!r})")
        if not (bad_s or names):
            assert "breakpoint" in out[2], out  # a legal s the core cannot probe


# --------------------------------------------------------------------------
# tr.solve_batch
# --------------------------------------------------------------------------

# Per-element absurd values: refused (the array is then named) or legal after all.
ELEMENT_INVALID = [math.nan, math.inf, -math.inf, "abc", None]
ELEMENT_LEGAL = [1e300, -1e300, 5e-324, -0.0, 2**70]  # not 10**400: finding B4


@st.composite
def point_arrays(draw, name, n, tail, scale, lo=-1.0):
    """``(value, kind)`` of one per-point argument: n rows of shape ``tail`` of
    ``scale * [lo, 1]`` values with ~3 % absurd elements, or at ~3 % an absurd
    argument.  kind: "legal", "invalid" (to be refused naming the argument), or
    "count" (another number of points: legal alone, a mismatch next to others)."""
    shape = (n,) + tail
    if absurd_here(draw):
        wrong = tail[:-1] + (tail[-1] + 1,) if tail else (2,)
        pool = [
            (np.zeros((n,) + wrong), "invalid"),
            (np.zeros((n, 2, 2, 2)), "invalid"),
            (0.1, "invalid"),
            ("abc", "invalid"),
            (np.zeros(shape, dtype=complex), "invalid"),
            (np.zeros(shape, dtype=object), "legal"),  # zeros as objects: numbers
            (np.asfortranarray(np.zeros(shape)), "legal"),
            (np.zeros(shape, dtype=np.float32), "legal"),
            (np.zeros((n + 1,) + tail), "count"),
            (np.zeros((0,) + tail), "count"),
        ]
        return draw(st.sampled_from(pool))
    size = int(np.prod(tail, dtype=int))
    flat = draw(st.lists(st.floats(lo, 1.0), min_size=n * size, max_size=n * size))
    vals, kind = [scale * x for x in flat], "legal"
    for i in range(len(vals)):
        if absurd_here(draw):
            v = vals[i] = draw(st.sampled_from(ELEMENT_INVALID + ELEMENT_LEGAL))
            if (
                v is None
                or isinstance(v, str)
                or not math.isfinite(v)
                or (name == "tension" and v < 0)
            ):
                kind = "invalid"
    arr = np.empty(shape, dtype=object)
    arr.reshape(-1)[:] = vals
    return arr.tolist(), kind


def point_scene(scene, k, arrays):
    """The scene of point ``k`` of a batch (the per-point values put into ``scene``)."""
    ctl = scene.displacement_controlled()
    disp, tens = list(scene.displacement), list(scene.tension)
    idisp = [i for i, c in enumerate(ctl) if c]
    iten = [i for i, c in enumerate(ctl) if not c]
    a = {key: None if v is None else np.asarray(v, dtype=float) for key, v in arrays.items()}
    if a.get("displacement") is not None:
        for j, i in enumerate(idisp):
            disp[i] = float(a["displacement"][k, j])
    if a.get("tension") is not None:
        for j, i in enumerate(iten):
            tens[i] = float(a["tension"][k, j])
    loads, j = [], 0
    for ld in scene.loads:
        if isinstance(ld, tr.PointLoad):
            f = ld.force if a.get("forces") is None else a["forces"][k, j]
            m = ld.moment if a.get("moments") is None else a["moments"][k, j]
            loads.append(tr.PointLoad(s=ld.s, force=f, moment=m))
            j += 1
        elif a.get("distributed") is None:
            loads.append(ld)
    if a.get("distributed") is not None:
        loads.append(tr.DistributedLoad(force=a["distributed"][k]))
    return dataclasses.replace(scene, displacement=disp, tension=tens, loads=loads)


def check_batch(r, n, tol, where):
    """Every point: a message; success exactly where the core vouches for it (status
    >= 0 except 3), and then finite, non-negative tensions and slacks, an orthonormal
    tip rotation and a residual within tol."""
    assert isinstance(r, tr.BatchResult) and len(r) == n, (where, r)
    for k in ("tip_position", "tension", "status", "message", "residual_norm", "success"):
        assert len(getattr(r, k)) == n, (where, k)
    for i in range(n):
        assert isinstance(r.message[i], str) and r.message[i], (where, i)
        st_ = int(r.status[i])
        assert bool(r.success[i]) == (st_ >= 0 and st_ != 3), (where, i, st_, r.message[i])
        if not r.success[i]:
            continue
        for k in ("tip_position", "tip_rotation", "tension", "slack", "displacement"):
            assert np.all(np.isfinite(getattr(r, k)[i])), (
                f"{where}: point {i} success, {k} not finite"
            )
        assert r.residual_norm[i] <= tol, (where, i, r.residual_norm[i])
        assert np.all(r.tension[i] >= 0) and np.all(r.slack[i] >= 0), (where, i)
        R = r.tip_rotation[i]
        # orthonormal to 1e-6: as check_raw_result (truncation error of the integrators)
        assert np.abs(R.T @ R - np.eye(3)).max() < 1e-6, (where, i)


def tip_tolerance(L, tol):
    # two converged solves of one scene from one cold start: the same iteration, but a
    # different formulation or verified step count moves the tip by the integrator's
    # truncation error (~1e-8 L at the automatic step count) or by the solver tolerance
    return max(1e-7, 100 * tol) * L


@entry_settings(250)
@given(spec=scene_specs(), ospec=options_specs(max_segments=16), data=st.data())
def test_solve_batch_entry(entry_worker, spec, ospec, data):
    """tr.solve_batch with drawn per-point arrays (displacement, tension, forces,
    moments, distributed; ~3 % absurd elements or arguments), threads, chunksize and
    options: a ValueError/TypeError naming the bad argument, or a result whose every
    point is an honest failure or a finite success; the first (cold) point agrees with
    tr.solve of its scene, and workers=2 is bitwise workers=1."""
    try:
        scene, accepted = build_scene(spec)
        arg, opts, opt_names, opt_acc = build_options(ospec, scene.robot.rod.length)
    except Refused:
        return
    refuse = set(opt_names)  # what the call must refuse
    ctl = scene.displacement_controlled()
    nd, nten, npl = sum(ctl), len(ctl) - sum(ctl), len(scene.point_loads)
    L, EI = scene.robot.rod.length, scene.robot.rod.bending_stiffness
    n = data.draw(st.integers(1, 4))
    arrays, counts = {}, {}
    for key, want, tail, scale, lo in (
        ("displacement", nd > 0, (nd,), 0.05 * L, -1.0),
        ("tension", nten > 0, (nten,), EI / (0.05 * L * L), 0.0),
        ("forces", npl > 0, (npl, 3), EI / L**2, -1.0),
        ("moments", npl > 0, (npl, 3), 0.3 * EI / L, -1.0),
        ("distributed", True, (3,), EI / L**3, -1.0),
    ):
        # an argument without columns (no such tendon or load: zeros of shape (n, 0...))
        # at ~3 %
        if not (want or absurd_here(data.draw)) or not data.draw(st.booleans()):
            continue
        if want:
            arrays[key], kind = data.draw(point_arrays(key, n, tail, scale, lo))
        else:
            arrays[key], kind = np.zeros((n,) + tail), "legal"
        if kind == "invalid":
            refuse.add(key)
        counts[key] = len(arrays[key]) if kind == "count" else n
    if len(set(counts.values())) > 1:  # the mismatch is reported at the later array
        refuse |= set(arrays)
    if not arrays and not absurd_here(data.draw):
        arrays["distributed"] = np.zeros((n, 3))
        counts["distributed"] = n
    if not arrays:
        refuse.add("displacement")  # "needs at least one of displacement, tension, ..."
    threads = data.draw(st.sampled_from([1, 1, 2, 2**70, np.int64(2)]))
    if absurd_here(data.draw):
        threads = data.draw(st.sampled_from([0, -1, 1.5, "2", None, True]))
        refuse.add("workers")
    chunksize = data.draw(st.sampled_from([None, 1, 2, 3, 2**70, HUGE]))
    if absurd_here(data.draw):
        chunksize = data.draw(st.sampled_from([0, -1, 2.0, "1", math.nan, True]))
        refuse.add("chunksize")
    kw = dict(arrays, options=arg, workers=threads, chunksize=chunksize)
    out = entry_worker.call("tendonrod.solve_batch", scene, **kw)
    if out[0] == "raise":
        check_call(out, refuse | accepted | opt_acc, "tr.solve_batch")
        return
    r = out[1]
    assert not refuse, f"tr.solve_batch accepted the absurd {sorted(refuse)}: {kw!r}"
    npts = len(r)
    assert npts == next(iter(counts.values())), (counts, npts)
    tol = opts.tol if opts is not None else tr.Options().tol
    check_batch(r, npts, tol, "tr.solve_batch")
    event(f"batch: {int(np.count_nonzero(r.success))}/{npts} converged")
    deterministic = opts is None or opts.max_time == 0.0
    if threads == 2 and deterministic:
        again = entry_worker.call("tendonrod.solve_batch", scene, **dict(kw, workers=1))
        assert again[0] == "ok", again
        assert np.array_equal(r.status, again[1].status), (r.status, again[1].status)
        assert np.array_equal(r.tip_position, again[1].tip_position, equal_nan=True)
    if npts and r.success[0] and deterministic:
        one_opts = dataclasses.replace(opts or tr.Options(), nodes=2, tip_only=True)
        single = entry_worker.call(
            "tendonrod.solve", point_scene(scene, 0, arrays), options=one_opts
        )
        assert single[0] == "ok", single
        sol = single[1]
        if sol.success and sol.formulation.planar == r.formulation["planar"]:
            err = np.abs(sol.tip_position - r.tip_position[0]).max()
            assert err <= tip_tolerance(L, tol), (err, sol.message, r.message[0])


# --------------------------------------------------------------------------
# tr.sweep
# --------------------------------------------------------------------------


def sweep_options(ospec, scene):
    """The options argument of a sweep: an Options (its nodes an int: finding B10) or
    None -- not a dict or another object (finding B5, AttributeError on the batch path)."""
    form, kw, bad = ospec
    if form in ("absurd", "dict", "none"):
        return None, tr.Options(tip_only=True)
    opts = construct("Options", tr.Options, kw, bad)
    if isinstance(opts.nodes, np.ndarray):
        opts = dataclasses.replace(opts, nodes=101)
    return opts, opts


@st.composite
def sweep_arguments(draw):
    """``(kwargs, absurd names)``: chunksize and workers, ~3 % absurd (not nan or
    strings: finding F12 of test_hostile.py and B9; not 10**400: B6)."""
    kw, names = {}, set()
    kw["chunksize"] = draw(st.sampled_from([None, 1, 2, 2**70]))
    if absurd_here(draw):
        kw["chunksize"] = draw(st.sampled_from([0, -1, -(2**70)]))
        names.add("chunksize")
    kw["workers"] = draw(st.sampled_from([1, 2]))
    if absurd_here(draw):
        kw["workers"] = draw(st.sampled_from([0, -2]))
        names.add("workers")
    return kw, names


def names_a_field(msg):
    """The message names a field: "Owner.field", or the core's "GJ = 1e+300" style."""
    core = r"\b(L|EI|GJ|EA|GA|rod|tendon \d+|load \d+|dist)\b"
    return bool(NAMED.search(msg) or re.search(core, msg))


def check_sweep(r, values, verdicts, varied, accepted, where):
    """Every point ran.  An invalid value is an OUTCOME_ERROR without a core status
    whose message names the varied field (``varied``: (owner, field)); a legal one is
    solved (OK exactly when the core vouches for it, finite values then), or refused
    naming another field it made invalid (a load beyond a shorter rod) or an absurd
    value of the base scene that its constructors ``accepted``."""
    outcome, status = np.asarray(r.outcome).ravel(), np.asarray(r.status).ravel()
    msgs = np.asarray(r.message).ravel()
    assert outcome.shape == (len(values),), (where, outcome)
    for i, v in enumerate(values):
        msg = msgs[i]
        assert isinstance(msg, str) and msg, (where, i)
        assert outcome[i] != OUTCOME_NOT_RUN, (where, i, msg)
        if outcome[i] == OUTCOME_ERROR:
            assert status[i] == STATUS_NONE, (where, i, status[i], msg)
            assert msg.startswith(("ValueError: ", "TypeError: ")), (where, v, msg)
            assert names_a_field(msg), f"{where}: value {v!r}: names no field: {msg!r}"
            named = [(o, f.split("[")[0]) for o, f, _ in NAMED.findall(msg)]
            if verdicts[i] == "invalid":
                assert named[:1] == [varied], f"{where}: value {v!r}: {msg!r}"
            elif verdicts[i] == "legal":
                assert accepted or (named and named[0] != varied), (
                    f"{where}: the legal value {v!r} was refused: {msg!r}"
                )
            event("sweep point: error")
            continue
        assert verdicts[i] != "invalid", f"{where}: {v!r} accepted: {msg}"
        assert status[i] != STATUS_NONE, (where, i, msg)
        ok = outcome[i] == OUTCOME_OK
        assert outcome[i] in (OUTCOME_OK, OUTCOME_NOT_CONVERGED), (where, i, outcome[i])
        assert ok == (status[i] >= 0 and status[i] != 3), (where, i, status[i], msg)
        if ok:
            for k in ("tip_position", "tip_rotation", "tension", "slack", "displacement"):
                val = np.asarray(r[k]).reshape(len(values), -1)[i]
                assert np.all(np.isfinite(val)), f"{where}: point {i} OK with {k} = {val}"
        event(f"sweep point: {'ok' if ok else 'not converged'}")


def compare_first_point(entry_worker, r, scene0, opts, where):
    """The first point of a sweep is a cold tr.solve of its scene: the same answer."""
    if r.outcome.ravel()[0] != OUTCOME_OK or opts.max_time != 0.0:
        return
    single = entry_worker.call("tendonrod.solve", scene0, options=opts)
    assert single[0] == "ok", single
    sol = single[1]
    assert sol.success, (
        f"{where}: the sweep's first point converged, tr.solve did not: {sol.message}"
    )
    err = np.abs(sol.tip_position - r["tip_position"].reshape(-1, 3)[0]).max()
    assert err <= tip_tolerance(scene0.robot.rod.length, opts.tol), (where, err)


@entry_settings(150)
@given(
    spec=scene_specs(point_load_first=True),
    ospec=options_specs(max_segments=16),
    args=sweep_arguments(),
    data=st.data(),
)
def test_sweep_batch_path_entry(entry_worker, spec, ospec, args, data):
    """tr.sweep(scene, {"loads[0].force[0]": values}) -- the batch path (solve_batch per
    chunk) when the options are tip-only, else per point -- with ~3 % absurd values and
    arguments: absurd arguments refused by name, absurd values recorded as errors naming
    the field, legal ones solved; the first point is tr.solve's answer."""
    try:
        scene, accepted = build_scene(spec)
        arg, opts = sweep_options(ospec, scene)
    except Refused:
        return
    F0 = scene.robot.rod.bending_stiffness / scene.robot.rod.length**2
    values = data.draw(st.lists(st.floats(-1.5, 1.5).map(lambda x: F0 * x), min_size=1, max_size=4))
    verdicts = ["legal"] * len(values)
    for i, v in enumerate(values):
        if absurd_here(data.draw):
            values[i] = data.draw(
                st.sampled_from(
                    [math.nan, math.inf, "abc", None, [1.0, 2.0], HUGE]
                    + [1e300, 5e-324, -0.0, np.float64(v), np.array(v)]
                    + [2**70]  # refused as "not a real number": finding B8
                )
            )
            v = values[i]
            invalid = (
                v is None
                or isinstance(v, (str, list))
                or v is HUGE
                or (isinstance(v, float) and not math.isfinite(v))
            )
            verdicts[i] = "invalid" if invalid else "either" if type(v) is int else "legal"
    kw, names = args
    path = "loads[0].force[0]"
    out = entry_worker.call(
        "tendonrod.sweep", scene, {path: values}, options=arg, progress=False, **kw
    )
    if out[0] == "raise":
        check_call(out, names, "tr.sweep (batch path)")
        return
    assert not names, f"tr.sweep accepted {kw}"
    r = out[1]
    check_sweep(r, values, verdicts, ("PointLoad", "force"), accepted, "tr.sweep (batch path)")
    if verdicts[0] == "legal":
        f = scene.point_loads[0]
        p0 = dataclasses.replace(f, force=(float(values[0]),) + f.force[1:])
        scene0 = dataclasses.replace(scene, loads=[p0 if ld is f else ld for ld in scene.loads])
        compare_first_point(entry_worker, r, scene0, opts, "tr.sweep (batch path)")


@entry_settings(150)
@given(
    spec=scene_specs(), ospec=options_specs(max_segments=16), args=sweep_arguments(), data=st.data()
)
def test_sweep_per_point_entry(entry_worker, spec, ospec, args, data):
    """tr.sweep(scene, {"robot.rod.length": values}) -- the per-point path -- with ~3 %
    absurd lengths: a length the Rod refuses is an error naming Rod.length; a legal one
    that leaves a load or a tendon anchor beyond the tip is an error naming that field;
    every other point is solved, and the first one is tr.solve's answer."""
    try:
        scene, accepted = build_scene(spec)
        arg, opts = sweep_options(ospec, scene)
    except Refused:
        return
    L = scene.robot.rod.length
    values = data.draw(st.lists(st.floats(0.6, 1.5).map(lambda x: L * x), min_size=1, max_size=3))
    verdicts = ["legal"] * len(values)
    for i, v in enumerate(values):
        if absurd_here(data.draw):
            values[i] = data.draw(
                st.sampled_from(
                    [math.nan, math.inf, -1.0, 0.0, -0.0, 5e-324, 1e300, "abc", None, [v], HUGE]
                    + [np.float64(v), np.array(v)]
                )
            )
            ok = isinstance(values[i], (np.floating, np.ndarray)) and np.ndim(values[i]) == 0
            verdicts[i] = "legal" if ok else "invalid"
    kw, names = args
    path = "robot.rod.length"
    out = entry_worker.call(
        "tendonrod.sweep", scene, {path: values}, options=arg, progress=False, **kw
    )
    if out[0] == "raise":
        check_call(out, names, "tr.sweep (per-point path)")
        return
    assert not names, f"tr.sweep accepted {kw}"
    r = out[1]
    check_sweep(r, values, verdicts, ("Rod", "length"), accepted, "tr.sweep (per-point path)")
    if verdicts[0] == "legal" and r.outcome.ravel()[0] == OUTCOME_OK:
        rob = scene.robot
        rod = dataclasses.replace(rob.rod, length=float(values[0]))
        scene0 = dataclasses.replace(scene, robot=dataclasses.replace(rob, rod=rod))
        compare_first_point(entry_worker, r, scene0, opts, "tr.sweep (per-point path)")


# --------------------------------------------------------------------------
# Reproducers of the bugs this module found (strict xfail: they flip when fixed)
# --------------------------------------------------------------------------


def _scene():
    rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    return tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=0.01)]),
        displacement=[0.004],
        loads=[tr.PointLoad(s=0.2, force=(-0.1, 0, 0))],
    )


@pytest.mark.parametrize("s", ["abc", 1j])
def test_compliance_names_s_for_non_numbers(s):
    """B1: a non-number s is refused naming s."""
    with pytest.raises((ValueError, TypeError)) as e:
        tr.compliance(_scene(), s=s)
    assert mentions(str(e.value), {"s"}), str(e.value)


def test_compliance_huge_int_s():
    """B2: an int beyond the float range as s is a ValueError naming s."""
    with pytest.raises(ValueError, match="s must"):
        tr.compliance(_scene(), s=10**400)


@pytest.mark.parametrize("s", ["abc", [0.1], np.array([0.1]), 10**400], ids=repr)
def test_problem_compliance_names_s(s):
    """B3: Problem.compliance refuses a bad s naming it, never OverflowError."""
    prob = tr.Problem(_scene())
    assert prob.solve().success
    with pytest.raises((ValueError, TypeError)) as e:
        prob.compliance(s)
    assert mentions(str(e.value), {"s"}), str(e.value)


@pytest.mark.parametrize("entry", ["solve guess", "solve_batch displacement"])
def test_huge_int_in_array_arguments(entry):
    """B4: 10**400 inside an array argument is a ValueError naming the argument."""
    with pytest.raises(ValueError) as e:
        if entry == "solve guess":
            tr.solve(_scene(), guess=[10**400] * 8)
        else:
            tr.solve_batch(_scene(), displacement=[[10**400]])
    assert entry.split()[1] in str(e.value), str(e.value)


@pytest.mark.parametrize("options", [{"steps": 5}, "fast"], ids=repr)
def test_sweep_batch_path_options_checked(options):
    """B5: the batch path of tr.sweep takes the options tr.solve takes (a dict) and
    refuses others naming options, as the per-point path does."""
    try:
        r = tr.sweep(_scene(), {"loads[0].force[0]": [0.1]}, options=options, progress=False)
    except (ValueError, TypeError) as e:
        assert "options" in str(e), str(e)
        return
    assert isinstance(options, dict) and r.success.all(), r.failures()


def test_sweep_huge_chunksize_runs_the_points():
    """B6: a huge chunksize runs every point in one chunk (or is refused by name)."""
    try:
        r = tr.sweep(_scene(), {"loads[0].force[0]": [0.1]}, chunksize=10**400, progress=False)
    except ValueError as e:
        assert "chunksize" in str(e)
        return
    assert (r.outcome != OUTCOME_NOT_RUN).all(), r.failures()


def test_time_limit_bounds_a_solve_with_many_nodes():
    """B7: max_time bounds the whole solve, filling 10**6 output nodes included.

    Measured in this thread's CPU time (the solve runs in it), not on the wall clock, so
    that a loaded machine does not fail it: the solve and the recording cost ~5 ms of
    CPU on the CI machine."""
    t0 = time.thread_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        sol = tr.solve(_scene(), options=tr.Options(nodes=10**6, max_time=1e-3))
    dt = time.thread_time() - t0
    # 0.1 s: 100x the limit asked for, room for allocating the 10**6-node output arrays
    assert dt < 0.1 * HANG_SCALE, (dt, sol.message)
    assert sol.position.shape == (10**6, 3) or not sol.success, sol.message


def test_vector_with_huge_finite_int():
    """B8: a finite int beyond int64 in a 3-vector is the real number it is."""
    assert tr.PointLoad(s=0.1, force=(2**70, 0, 0)).force[0] == 2.0**70


def test_sweep_names_workers():
    """B9: a non-integer workers is refused naming workers."""
    with pytest.raises((ValueError, TypeError), match="workers"):
        tr.sweep(_scene(), {"loads[0].force[0]": [0.1]}, workers="two", progress=False)


def test_tip_position_is_the_tip_whatever_the_nodes():
    """B10: Solution.tip_position is the state at s = L whatever the output nodes."""
    want = tr.solve(_scene()).tip_position
    got = tr.solve(_scene(), options=tr.Options(nodes=[0.0, 0.1])).tip_position
    # 1e-7 L: both solves converge to tol 1e-10 with the automatic step count
    assert np.abs(got - want).max() < 1e-7 * 0.2, (got, want)


@pytest.mark.parametrize("field", ["max_work", "max_time", "rtol", "tol"])
def test_options_huge_int(field):
    """B11: an int beyond the float range in a real-valued option is refused by name."""
    with pytest.raises(ValueError, match=f"Options.{field}"):
        tr.Options(**{field: 10**400})


def test_cosserat_rod_rigid_in_extension():
    """B12: a Cosserat rod with EA = inf solves, or is refused naming Rod.EA."""
    try:
        rod = tr.Rod(length=0.2, EI=4e-3, GJ=3e-3, EA=math.inf, GA=4e4)
        scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=0.2, force=(0.1, 0, 0))])
        sol = tr.solve(scene)
    except ValueError as e:
        assert "Rod.EA" in str(e), str(e)
        return
    assert sol.success, sol.message


def test_problem_compliance_after_a_failed_solve(rod):
    """B13: Problem.compliance linearises at the last successful solution even when a
    later solve failed."""
    loads = [tr.PointLoad(s=0.2, force=(-0.1, 0.05, 0))]  # out of plane: spatial
    scene = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), displacement=[0.004], loads=loads)
    hopeless = dataclasses.replace(scene, displacement=[0.5])  # 2.5 L: no equilibrium
    prob = tr.Problem(scene, options=tr.Options(continuation=False))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        assert prob.solve().success
        assert not prob.solve(hopeless).success
    C = prob.compliance()
    # 1e-6 relative: both linearise the same equilibrium, converged to tol 1e-10
    want = tr.compliance(scene)
    assert np.allclose(C, want, rtol=1e-6, atol=1e-6 * np.abs(want).max()), (C, want)


def test_compliance_budget_exhausted_is_a_convergence_error():
    """B14: a compliance whose budget runs out is an honest ConvergenceError."""
    rod = tr.Rod(length=0.2, EI=4e-3, GJ=3.08e-3, EA=8e4, GA=3.2e4)
    scene = tr.Scene(tr.Robot(rod, []))
    for max_work in (1e3, 2e3, 3e3, 5e3, 1e4, 2e4):  # around where the linearisation runs out
        try:
            C = tr.compliance(scene, options=tr.Options(max_work=max_work))
        except tr.ConvergenceError:
            continue
        assert C.shape == (6, 6) and np.all(np.isfinite(C))
