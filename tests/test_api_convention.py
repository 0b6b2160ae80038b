"""One API convention, checked over every entry point: the failure rule (a warning by
default, ConvergenceError with strict=True), the common result fields (tr.Result),
keyword-only options, the old spellings (each warns once and still works), read-only
solutions, the public namespace, plots on a given and on no Axes, and the small helpers
(taut, Tendon.ring, the slack tendon an actuation names)."""

import inspect
import warnings

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import tendonrod as tr  # noqa: E402

ROD = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
# one iteration, no continuation: a bare rod under a tip load of F L^2/EI ~ 10 cannot
# converge (the ConvergenceWarning docstring's example)
HOPELESS = tr.Options(max_iter=1, continuation=False)


def _loaded(force=1.0):
    return tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(s=0.2, force=(force, 0.0, 0.0))])


def _pair():
    """Two opposite tendons (finite EA: determinate), both at rest."""
    return tr.Scene(tr.Robot(ROD, list(tr.Tendon.ring(2, 0.01, EA=3e3))), displacement=[0.0, 0.0])


def _fit_scenes():
    return [_loaded(-0.02)]


# every entry point that can fail: (name, a call that fails, given strict=...)
FAILING = {
    "solve": lambda strict: tr.solve(_loaded(), options=HOPELESS, strict=strict),
    "Problem.solve": lambda strict: tr.Problem(_loaded(), options=HOPELESS).solve(strict=strict),
    "solve_batch": lambda strict: tr.solve_batch(
        _loaded(), forces=[[[1.0, 0.0, 0.0]]], options=HOPELESS, strict=strict
    ),
    "sweep": lambda strict: tr.sweep(
        _loaded(),
        {"loads[0].force": [(1.0, 0.0, 0.0)]},
        grid=False,
        options=HOPELESS,
        progress=False,
        strict=strict,
    ),
    # two points cannot reach the end of the span
    "path": lambda strict: tr.path(
        _loaded(0.0), "loads[0].force[0]", (0.0, 0.5), max_points=2, strict=strict
    ),
    "jacobian": lambda strict: tr.jacobian(_loaded(), options=HOPELESS, strict=strict),
    # a tendon only pulls: bending the other way with tendon 0 alone cannot be done
    "actuate": lambda strict: tr.actuate(_pair(), tip_angle=-0.5, tendons=[0], strict=strict),
    # one evaluation: SciPy's budget is spent before any convergence test is met
    "fit": lambda strict: tr.fit(
        _fit_scenes(),
        [
            tr.solve(
                tr.Scene(
                    tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True, EI=4.6e-3), []),
                    loads=[tr.PointLoad(s=0.2, force=(-0.02, 0, 0))],
                )
            ).tip_position
        ],
        ["EI"],
        max_iter=1,
        strict=strict,
    ),
}


@pytest.mark.parametrize("name", sorted(FAILING))
def test_failure_rule_warns_by_default_and_raises_when_strict(name):
    call = FAILING[name]
    with pytest.warns(tr.ConvergenceWarning) as rec:
        res = call(False)
    assert rec[0].filename == __file__  # attributed to the caller's line
    assert isinstance(res, tr.Result)
    assert not np.all(res.success)
    with pytest.raises(tr.ConvergenceError) as err:
        call(True)
    assert isinstance(err.value.solution, tr.Result) and not np.all(err.value.solution.success)


def test_compliance_always_raises():
    with pytest.raises(tr.ConvergenceError, match="did not solve"):
        tr.compliance(_loaded(), options=HOPELESS)
    assert "always" in tr.compliance.__doc__


FIELDS = ("success", "status", "message", "nit", "nfev")


def test_every_result_type_has_the_common_fields():
    robot = tr.Robot(ROD, [tr.Tendon(0.01)])
    scene = tr.Scene(robot, displacement=[0.005])
    sol = tr.solve(scene)
    results = [
        sol,
        tr.Problem(scene).solve(),
        tr.solve_batch(scene, displacement=[[0.004], [0.005]]),
        tr.sweep(scene, {"displacement[0]": [0.004, 0.005]}, progress=False),
        tr.path(scene, "displacement[0]", (0.0, 0.005)),
        tr.jacobian(scene),
        tr.actuate(scene, tip_angle=0.3),
        tr.actuate(scene, tip_angle=0.3).actuation,
    ]
    for res in results:
        assert isinstance(res, tr.Result), type(res).__name__
        for f in FIELDS:
            assert hasattr(res, f), (type(res).__name__, f)
        assert np.all(res.success) and np.all(np.asarray(res.status) >= 0), type(res).__name__
    assert set(FIELDS) <= {f.name for f in tr.FitResult.__dataclass_fields__.values()}
    for cls in (tr.Solution, tr.BatchResult, tr.SweepResult, tr.Branch, tr.Jacobian, tr.FitResult):
        assert "tendonrod.Result" in cls.__doc__, cls.__name__


ENTRY_POINTS = {
    "solve": tr.solve,
    "Problem": tr.Problem.__init__,
    "compliance": tr.compliance,
    "jacobian": tr.jacobian,
    "solve_batch": tr.solve_batch,
    "sweep": tr.sweep,
    "path": tr.path,
    "actuate": tr.actuate,
    "fit": tr.fit,
}


@pytest.mark.parametrize("name", sorted(ENTRY_POINTS))
def test_options_keyword_only_and_one_spelling(name):
    params = inspect.signature(ENTRY_POINTS[name]).parameters
    assert params["options"].kind is inspect.Parameter.KEYWORD_ONLY
    if name in ("solve_batch", "sweep"):
        assert "workers" in params and not {"threads", "max_workers"} & set(params)
    if name in ("actuate", "fit"):
        assert {"tol", "max_iter"} <= set(params) and not {"xtol", "max_nfev"} & set(params)
    if name not in ("compliance", "Problem"):
        assert params["strict"].kind is inspect.Parameter.KEYWORD_ONLY


def _warns_once(call, match):
    """``call()`` twice: a DeprecationWarning naming ``match`` the first time only."""
    with pytest.warns(DeprecationWarning, match=match):
        first = call()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        second = call()
    return first, second


def test_old_spellings_warn_once_and_work(tmp_path):
    robot = tr.Robot(ROD, [tr.Tendon(0.01)])
    scene = tr.Scene(robot, displacement=[0.005])
    opts = tr.Options(tip_only=True)
    a, b = _warns_once(lambda: tr.solve(scene, None, opts), "tendonrod.solve with options=")
    assert a.options == opts and np.array_equal(a.tip_position, b.tip_position)
    p, _ = _warns_once(lambda: tr.Problem(scene, opts), "tendonrod.Problem with options=")
    assert p.options == opts
    C, _ = _warns_once(lambda: tr.compliance(scene, None, None, opts), "compliance with options=")
    np.testing.assert_array_equal(C, tr.compliance(scene, options=opts))  # the same call
    q = [[0.004], [0.005]]
    r, _ = _warns_once(lambda: tr.solve_batch(scene, displacement=q, threads=2), r"threads=\)")
    np.testing.assert_array_equal(
        r.tip_position, tr.solve_batch(scene, displacement=q).tip_position
    )
    vary = {"displacement[0]": [0.004, 0.005]}
    s, _ = _warns_once(
        lambda: tr.sweep(scene, vary, max_workers=1, progress=False), r"max_workers=\)"
    )
    assert s.success.all()
    _warns_once(
        lambda: tr.sweep(scene, vary, path=tmp_path / "s.jsonl", progress=False), r"path=\)"
    )
    assert (tmp_path / "s.jsonl").exists()
    with pytest.raises(TypeError, match="workers= only"):
        tr.sweep(scene, vary, workers=1, max_workers=1, progress=False)
    meas = [tr.solve(_loaded(-0.02)).tip_position]
    f, _ = _warns_once(lambda: tr.fit(_fit_scenes(), meas, ["EI"], xtol=1e-10), r"xtol=\)")
    assert f.success
    _warns_once(lambda: tr.fit(_fit_scenes(), meas, ["EI"], max_nfev=50), r"max_nfev=\)")
    Path, _ = _warns_once(lambda: tr.Path, "tendonrod.Path is deprecated")
    assert Path is tr.Branch
    branch = tr.path(scene, "displacement[0]", (0.0, 0.005))
    ax, _ = _warns_once(lambda: tr.plot.path(branch), "tendonrod.plot.branch")
    assert ax.get_lines()
    plt.close("all")


def test_solution_is_read_only():
    sol = tr.solve(tr.Scene(tr.Robot(ROD, [tr.Tendon(0.01)]), displacement=[0.005]))
    for name, value in (("success", False), ("message", ""), ("tension", None), ("extra", 1)):
        with pytest.raises(AttributeError, match="read-only"):
            setattr(sol, name, value)
    with pytest.raises(AttributeError, match="read-only"):
        del sol.status
    assert sol.success and sol.position.shape[1] == 3  # the lazy outputs still fill
    # nor can its arrays be edited in place (a copy can)
    for name in ("tension", "slack", "displacement", "tip_position", "position", "rotation"):
        arr = getattr(sol, name)
        with pytest.raises(ValueError, match="read-only"):
            arr[...] = 0.0
        copy = np.array(arr)
        copy[...] = 0.0


PUBLIC_MODULES = {
    "analytic",
    "plot",
    "paper",
    "scenefile",
    "routing",
    "sweeps",
    "continuation",
    "bench",
}


def test_no_private_names_in_the_namespace():
    names = set(dir(tr))
    assert names == set(tr.__all__) | PUBLIC_MODULES
    assert not [n for n in names if n.startswith("_") and n != "__version__"]
    assert len(tr.__all__) == len(set(tr.__all__))
    for helper in ("import_core", "make_callable", "read_solution", "compiled", "TYPE_CHECKING"):
        assert helper not in names
    assert inspect.isfunction(tr.sweep) and inspect.isfunction(tr.path)


def test_plots_on_a_given_and_on_no_axes():
    robot = tr.Robot(ROD, [tr.Tendon(0.01)])
    scene = tr.Scene(robot, displacement=[0.0])
    branch = tr.path(scene, "displacement[0]", (0.0, 0.005))
    plt.close("all")
    ax = tr.plot.branch(branch)
    assert ax is not None and len(plt.get_fignums()) == 1
    fig, given = plt.subplots()
    assert tr.plot.branch(branch, ax=given) is given and len(plt.get_fignums()) == 2
    plt.close("all")


def test_taut_mask_ring_and_the_slack_tendon_named():
    ring = tr.Tendon.ring(4, 0.01, phase=0.1, EA=3e3)
    np.testing.assert_allclose([t.angle for t in ring], 0.1 + np.arange(4) * np.pi / 2)
    assert all(t.offset == 0.01 and t.EA == 3e3 for t in ring)
    with pytest.raises(ValueError, match="n must be an int >= 1"):
        tr.Tendon.ring(0, 0.01)
    # tendon 0 pulled, the opposite one paid out further than the bend lengthens its
    # channel: the first taut, the second slack
    ring2 = list(tr.Tendon.ring(2, 0.01, EA=3e3))
    scene = tr.Scene(tr.Robot(ROD, ring2), displacement=[0.005, -0.01])
    sol = tr.solve(scene)
    assert sol.taut.tolist() == [True, False] and sol.slack[1] > 0
    batch = tr.solve_batch(scene, displacement=[[0.005, -0.01], [-0.01, 0.005]])
    assert batch.taut.tolist() == [[True, False], [False, True]]
    with pytest.warns(tr.ConvergenceWarning, match="tendon 0 went slack") as rec:
        tr.actuate(_pair(), tip_angle=-0.5, tendons=[0])
    assert "would need tendon 1" in str(rec[0].message)
