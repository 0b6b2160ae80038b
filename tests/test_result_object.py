"""The result a lazy solve of a compiled problem returns (``_core.Result``): the same
fields as the solve dict, built on first access, and a Solution made from it that is
indistinguishable from one made from the dict (fields, raw, pickling, flags)."""

from __future__ import annotations

import math
import pickle

import numpy as np

import tendonrod as tr
from tendonrod import _core
from tendonrod.compiled import _compile
from tendonrod.solution import _FIELDS, Solution


def _robot():
    rod = tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9)
    return tr.Robot(rod, [tr.Tendon(offset=0.01, angle=a) for a in (0.0, math.pi / 2)])


def _scene(f=0.05):
    return tr.Scene(
        _robot(),
        displacement=[3e-3, None],
        tension=[None, 1.0],
        loads=[tr.PointLoad(s=0.2, force=(0.0, f, 0.0))],
    )


def _same(a, b):
    """Bitwise equality (arrays by dtype, shape and bytes; NaN equals NaN)."""
    if isinstance(a, np.ndarray):
        return (
            isinstance(b, np.ndarray)
            and a.dtype == b.dtype
            and a.shape == b.shape
            and (a.tobytes() == b.tobytes())
        )
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, tuple):
        return isinstance(b, tuple) and len(a) == len(b) and all(map(_same, a, b))
    if isinstance(a, float) and math.isnan(a):
        return isinstance(b, float) and math.isnan(b)
    return type(a) is type(b) and a == b


def test_result_is_the_solve_dict():
    """A lazy solve's Result holds exactly what the same solve's dict holds (the node
    arrays aside, which a lazy solve leaves to the recording): the same keys and the same
    values, bit for bit, through item access, attributes, get, in and as_dict."""
    scene = _scene()
    opts = tr.Options()
    lazy = _compile(scene, opts).solve(warm=False, record=False)
    eager = _compile(scene, opts).solve(warm=False, record=True)
    assert type(lazy) is _core.Result and type(eager) is dict
    d = lazy.as_dict()
    nodes = {"s", "position", "rotation", "force", "moment", "tendon_tension", "tendon_rest"}
    assert d.keys() == eager.keys() - nodes
    for key in d:
        # the recording pass adds its integrations to nfev and work, and the displacements
        # of the tension-controlled tendons: those differ by design
        if key not in ("nfev", "work", "displacement"):
            assert _same(d[key], eager[key]), key
        assert _same(lazy[key], d[key]) and _same(getattr(lazy, key), d[key]), key
        assert key in lazy and lazy.get(key) is d[key]
    assert len(lazy) == len(d) and list(lazy) == list(d) and list(lazy.keys()) == list(d)
    assert "position" not in lazy and lazy.get("position", 7) == 7
    assert lazy.stability_verdict is not None  # judged: a default solve
    # pickled, a Result is its dict
    assert _same(pickle.loads(pickle.dumps(lazy)), d)


def test_no_verdict_key_without_a_verdict():
    """With accept_unstable the solve judges no stability: no stability_verdict key (the
    attribute reads None), as in the dict."""
    opts = tr.Options(accept_unstable=True)
    res = _compile(_scene(), opts).solve(warm=False, record=False)
    assert "stability_verdict" not in res and res.stability_verdict is None
    assert "stability_verdict" not in res.as_dict()


def test_solution_from_result_equals_solution_from_dict():
    """A Solution of a Result and one of the same Result's dict agree on every field, the
    node arrays, the verdict and the raw dict; the arrays keep their flags (the core's
    outputs read-only, the base state a fresh writeable array)."""
    scene = _scene()
    prob = tr.Problem(scene)
    a = prob.solve()
    assert type(a.__dict__["_res"]) is _core.Result
    b = Solution(a._res.as_dict(), scene, prob.options)
    for name in sorted(_FIELDS):
        assert _same(getattr(a, name), getattr(b, name)), name
    for name in (
        "tip_position",
        "tip_rotation",
        "base_state",
        "displacement",
        "position",
        "rotation",
        "tendon_tension",
    ):
        assert _same(getattr(a, name), getattr(b, name)), name
    assert a.stable == b.stable and a.stability_reason == b.stability_reason
    assert a.formulation == b.formulation and repr(a) == repr(b)
    assert a.tension is a.raw["tension"]  # one object, whichever way it is read
    assert not a.tension.flags.writeable and not a.tip_position.flags.writeable
    assert a.base_state.flags.writeable


def test_solution_of_result_pickles_and_warm_starts():
    """Pickled, a Solution carries its fields and its raw dict (not the core's object);
    the unpickled one warm-starts a solve as the original does (nit 0 at its own scene)."""
    scene = _scene()
    sol = tr.Problem(scene).solve()
    back = pickle.loads(pickle.dumps(sol))
    assert back.__dict__["_res"] is None and type(back.raw) is dict
    assert _same(back.raw, sol.raw)
    for name in sorted(_FIELDS):
        assert _same(getattr(back, name), getattr(sol, name)), name
    again = tr.solve(scene, guess=back)
    assert again.success and again.nit == 0


def test_result_fields_are_read_only():
    """A Solution of a Result is read-only like any Solution, and its fields are built
    once (the same object on every access)."""
    sol = tr.Problem(_scene()).solve()
    assert sol.jacobian is sol.jacobian and sol.unknowns is sol.unknowns
    for name in ("success", "tension", "raw", "nit"):
        try:
            setattr(sol, name, None)
        except AttributeError:
            pass
        else:  # pragma: no cover
            raise AssertionError(f"Solution.{name} was writable")
