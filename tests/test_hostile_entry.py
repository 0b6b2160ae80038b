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
refusal by a constructor is checked to name the field.  Every example also runs under a
hypothesis deadline of a few seconds: the default work budget keeps a hopeless solve
under about 0.5 s, so an example that takes longer is a hang.

Known bugs found by this module are excluded from the random draws (the comment at each
exclusion names the strict-xfail reproducer at the end of the file), so that the random
tests stay green and the reproducers flip when the bugs are fixed.
"""

import dataclasses
import math
import os
import pickle
import re
import time
import warnings
from datetime import timedelta

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
from tendonrod.sweep import (
    OUTCOME_ERROR,
    OUTCOME_NOT_CONVERGED,
    OUTCOME_NOT_RUN,
    OUTCOME_OK,
    STATUS_NONE,
)

# --------------------------------------------------------------------------
# Harness: the worker of test_hostile.py, able to import this module
# --------------------------------------------------------------------------

TESTS_DIR = os.path.dirname(os.path.abspath(__file__))

# Hang guard of one worker call [s] (Worker.call multiplies it by HANG_SCALE): far above
# the ~0.5 s the default work budget allows a hopeless solve, so only a hang trips it.
CALL_TIMEOUT = 60.0

# Per-example deadline: a Problem example makes up to 8 solves, each bounded by its work
# budget (at most the default 1.5e7 units, ~0.5 s); 8 s leaves room for a loaded 2-core
# machine; instrumented runs (make sanitize) stretch it by HANG_SCALE.
DEADLINE = timedelta(seconds=8.0 * HANG_SCALE)


def entry_settings(n):
    """test_hostile's settings (derandomized, no database; ``TR_HOSTILE_PROFILE=explore``
    multiplies the examples by 10) with ``n`` examples and this module's deadline."""
    return settings(hostile(n), deadline=DEADLINE)


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
NAMED = re.compile(r"\b(Rod|Tendon|Robot|PointLoad|DistributedLoad|Scene|Options)(?:\.(\w+(?:\[\d+\])?)|: (tendon) \d+)")


def check_refusal(exc, owner, absurd, where=""):
    """``exc``, raised by constructing ``owner`` with the absurd values ``absurd``
    (field -> value; empty: a legal combination was refused), is a ValueError/TypeError
    that names a field of ``owner`` -- an absurd one (or one derived from it, whose
    message then quotes the absurd field) -- and shows a scalar's value."""
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
        assert field in absurd or base in absurd or any(f"{k}=" in msg or f"{k}[" in msg for k in absurd), (
            f"{owner}{where}: refused {absurd!r} but names {field!r}: {msg!r}"
        )
    if field in absurd:
        assert _names_field(msg, field, absurd[field]), (
            f"{owner}{where}: the message does not show {field}={absurd[field]!r}: {msg!r}"
        )


class Refused(Exception):
    """A constructor refused the drawn value (and the refusal has been checked)."""


def construct(owner, ctor, kwargs, absurd, where=""):
    try:
        return ctor(**kwargs)
    except Exception as e:  # noqa: BLE001 - the type is part of what is checked
        check_refusal(e, owner, absurd, where)
        event(f"refused by {owner}")
        raise Refused(owner) from None


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
        EA = draw(st.sampled_from([2e7 * EI, math.inf]))
        GA = draw(st.sampled_from([8e6 * EI, math.inf]))
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
            t = dict(
                offset=b, angle=phase + 2 * math.pi * i / nt, slope=slope, EA=EA_t, end=end
            )
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
        loads.append(("PointLoad", *inject(draw, dict(s=s, force=vec(EI / L**2), moment=m), vpools)))
    if npl < 2 and draw(st.booleans()):
        loads.append(("DistributedLoad", *inject(draw, dict(force=vec(EI / L**3)), vpools)))
    spec["loads"] = loads
    if absurd_here(draw):
        act["loads"] = act_bad["loads"] = draw(st.sampled_from([5, "x", [None], [tr.Tendon()]]))
    spec["scene"] = (act, act_bad)
    return spec


def build_scene(spec):
    """The Scene of ``spec``; :class:`Refused` (after checking the refusal) when a
    constructor refuses it."""
    rod = construct("Rod", tr.Rod, *spec["rod"])
    check_accepted(rod)
    tendons = []
    for i, (kw, bad) in enumerate(spec["tendons"]):
        tendons.append(construct("Tendon", tr.Tendon, kw, bad, f" (tendon {i})"))
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
            loads.append(construct(cls, getattr(tr, cls), lkw, lbad))
            check_accepted(loads[-1])
        kw["loads"] = loads
    return construct("Scene", lambda **k: tr.Scene(robot, **k), kw, bad)


# --------------------------------------------------------------------------
# Options
# --------------------------------------------------------------------------

DEFAULT_MAX_WORK = tr.Options().max_work


def absurd_nodes(v):
    return st.sampled_from(
        [0, 1, -1, 10**7 + 1, 2**70, 2.5, math.nan, [math.nan], [0.5, 0.1], [], [-0.1], [0.0, 1e300]]
        + ["abc", None, np.array(3), [[0.0, 0.01]], np.zeros((2, 2))]
    )


def absurd_choice(v):
    return st.sampled_from(["RK8", "rk4 ", "", "sensitivity", None, 3, b"fd", [v], np.array([v])])


def absurd_int(v):
    return st.sampled_from([-1, 0, 2**31, 2**70, HUGE, 2.5, float(v), "3", None, True, math.nan, np.int64(v), np.array(v)])


def absurd_real(v):
    return st.sampled_from([math.nan, math.inf, -1.0, 0.0, -0.0, 5e-324, 1e300, 2.0, "1e-8", None, True, np.float64(v), np.array(v), [v], HUGE])


OPTION_POOLS = {
    "integrator": absurd_choice,
    "jacobian_method": absurd_choice,
    "slack_model": absurd_choice,
    "nodes": absurd_nodes,
    **{k: absurd_int for k in ("steps", "max_iter", "max_nfev", "max_continuation", "shooting_segments")},
    **{k: absurd_real for k in ("rtol", "tol", "max_work", "max_time")},
}


@st.composite
def options_specs(draw, L=0.2):
    """``(form, kwargs, absurd)``: mostly-legal values of every Options field (a small
    work budget for speed, the default one in 1 example of 8), ~3 % absurd, passed as
    an Options (mostly), a dict or None; at ~3 % the options argument itself is absurd."""
    if absurd_here(draw):
        bad = draw(st.sampled_from(["fast", 3, {"nonsense": 1}, {"steps": -1}, tr.Rod]))
        return ("absurd", bad, {"options": bad})
    nodes = draw(
        st.one_of(
            st.sampled_from([101, 2, 9]),
            # arc lengths in [0, L]; not 10**7 nodes (the legal maximum): finding B7
            st.lists(st.floats(0.0, 1.0), min_size=1, max_size=5).map(
                lambda f: [L * x for x in sorted(f)]
            ),
        )
    )
    legal = dict(
        integrator=draw(st.sampled_from(["rk8", "rk8", "rk4", "adaptive"])),
        steps=draw(st.sampled_from([0, 0, 0, 8, 40, 300])),
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
        shooting_segments=draw(st.sampled_from([1, 1, 1, 2, 5, 64])),
        # 2e6 units ~ 70 ms: a hopeless solve gives up quickly; the default (~0.5 s)
        # in 1 of 8 examples checks that it bounds a hopeless solve as documented
        max_work=draw(st.sampled_from([2e6] * 5 + [DEFAULT_MAX_WORK, 1e4, 1.0])),
        max_time=draw(st.sampled_from([0.0] * 8 + [1e-3, 5e-324])),
    )
    kw, bad = inject(draw, legal, OPTION_POOLS)
    form = draw(st.sampled_from(["Options"] * 6 + ["dict", "none"]))
    return (form, kw, bad)


def build_options(spec):
    """``(options argument, Options or None for the defaults, absurd names)``;
    :class:`Refused` when Options refuses the drawn values."""
    form, kw, bad = spec
    if form == "absurd":
        names = {"options", "nonsense", "steps"}
        return kw, None, names
    if form == "none":
        return None, tr.Options(), set()
    opts = construct("Options", tr.Options, kw, bad)
    return (opts if form == "Options" else dict(kw)), opts, set()


def nodes_reach_tip(opts):
    return not isinstance(opts.nodes, np.ndarray) or opts.nodes[-1] == opts.nodes.max() and False


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
    assert mentions(out[2], names), f"{where}: the refusal names none of {sorted(names)}: {out[2]!r}"
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
        return draw(st.sampled_from(["warm", "", 3.0, np.array(1.0), "short", "nan", "long", {"a": 1}])), True
    return draw(st.sampled_from([None, None, "cold", "base", "zeros", "random"])), False


def make_guess(kind, nt, draw_floats):
    n = 6 + 2 * nt
    return {
        "base": base_solution() if kind == "base" else None,
        "zeros": np.zeros(n),
        "random": np.array(draw_floats(n)),
        "short": np.zeros(n - 1),
        "long": np.zeros(n + 1),
        "nan": np.full(n, np.nan),
    }.get(kind, kind) if isinstance(kind, str) else kind


@entry_settings(60)
@given(spec=scene_specs(), ospec=options_specs(), g=guesses(), data=st.data())
def test_solve_entry(entry_worker, spec, ospec, g, data):
    """tr.solve(scene, guess=..., options=...) on drawn scenes, options and guesses:
    constructors refuse absurd fields by name; the solve refuses an absurd guess or
    options argument by name, and otherwise returns an honest failure or a correct,
    NaN-free solution -- within the deadline, without a crash."""
    try:
        scene = build_scene(spec)
        arg, _, names = build_options(ospec)
    except Refused:
        return
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
        if guess == "first":
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
    """``scene`` with other values only: actuation redrawn (~3 % absurd), loads and
    pretensions scaled by nonzero factors (a zero stays zero: planarity is kept)."""
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
            loads.append(tr.PointLoad(s=ld.s, force=[c * x for x in ld.force], moment=[c * x for x in ld.moment]))
        else:
            loads.append(tr.DistributedLoad(force=[c * x for x in ld.force]))
    robot = tr.Robot(rob.rod, [dataclasses.replace(t, pretension=cp * t.pretension) for t in rob.tendons])
    try:
        return construct(
            "Scene",
            lambda **k: tr.Scene(robot, **k),
            dict(displacement=disp, tension=tens, loads=loads),
            bad,
            " (same structure)",
        )
    except Refused:
        return None


def absurd_s(L):
    # not strings, complex, lists, arrays or 10**400: findings B1-B3 (tr.compliance and
    # Problem.compliance do not name s, or raise OverflowError)
    return st.sampled_from([math.nan, math.inf, -math.inf, -0.0, 0.0, -L, 2 * L, 1e300, 5e-324, 2**70, L * (1 + 1e-13), np.float64(L)])


@st.composite
def arc_lengths(draw, L):
    """``(s, absurd?)`` for compliance: None (the tip) mostly, or a point in (0, L]."""
    if absurd_here(draw):
        return draw(absurd_s(L)), True
    return draw(st.one_of(st.none(), st.none(), st.floats(0.05, 1.0).map(lambda f: f * L))), False


SOLVE_STEPS = ("solve()", "solve(same)", "solve(cold)", "solve(guess)")


@entry_settings(40)
@given(spec=scene_specs(), ospec=options_specs(), data=st.data())
def test_problem_entry(entry_worker, spec, ospec, data):
    """tr.Problem(scene, options) and everything it offers, in one child: solve()
    (cold), solve(same structure, other values), solve(another structure) -> ValueError
    naming the differing field, solve(guess="cold"), solve(guess=first solution or a
    drawn guess), compliance(s), and a pickled copy (scene and options kept, warm state
    dropped) whose solve() is bitwise the first one."""
    try:
        scene = build_scene(spec)
        arg, opts, names = build_options(ospec)
    except Refused:
        return
    same = same_structure(data.draw, scene)
    muts = _mutations(scene)
    which = data.draw(st.sampled_from(sorted(muts)))
    try:
        other = muts[which]()
    except ValueError as e:  # the changed design is itself refused (e.g. pretension)
        check_refusal(e, type(e).__name__ and NAMED.search(str(e)).group(1), {})
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
    assert not names, f"tr.Problem accepted options={arg!r}"
    checked = {}
    for step, sc in (("solve()", scene), ("solve(same)", same), ("solve(cold)", scene)):
        if step in res:
            checked[step] = check_solve_outcome(sc, res[step], set(), f"Problem.{step}")
    checked["solve(guess)"] = check_solve_outcome(
        scene, res["solve(guess)"], {"guess"} if bad_guess else set(), "Problem.solve(guess)"
    )
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
        assert not any_success, c
        event("compliance: no solution yet")
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


@entry_settings(40)
@given(spec=scene_specs(), ospec=options_specs(), data=st.data())
def test_compliance_entry(entry_worker, spec, ospec, data):
    """tr.compliance(scene, s=..., options=...): a finite (6, 6) matrix, an honest
    ConvergenceError when the scene does not solve, or a ValueError/TypeError naming
    s (or options) -- never another exception, a crash or a hang."""
    try:
        scene = build_scene(spec)
        arg, _, names = build_options(ospec)
    except Refused:
        return
    s, bad_s = data.draw(arc_lengths(scene.robot.rod.length))
    out = entry_worker.call("tendonrod.compliance", scene, s=s, options=arg)
    if out[0] == "ok":
        C = np.asarray(out[1])
        assert C.shape == (6, 6) and np.all(np.isfinite(C)), C
        assert not names and not bad_s or s in (2**70,) or s == scene.robot.rod.length, (s, arg)
        event("compliance: ok")
    elif raised(out, tr.ConvergenceError):
        assert "did not solve" in out[2], out
        event("compliance: ConvergenceError")
    else:
        check_call(out, names | {"s"} if (bad_s or names) else {"s"}, f"tr.compliance(s={s!r})")
        if not (bad_s or names):
            assert "breakpoint" in out[2], out  # a legal s the core cannot probe
