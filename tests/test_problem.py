"""tr.Problem: a scene's structure compiled once, values per call, warm state in C."""

from __future__ import annotations

import math
import pickle
import threading
import warnings

import numpy as np
import pytest

import tendonrod as tr

# The fixture robot's displacements compress its backbone by ~7 % (the 2 % strain rule of
# tendonrod.plausibility warns); these tests are about Problem's mechanics, so that
# expected warning is let through (the suite turns every other warning into an error).
pytestmark = pytest.mark.filterwarnings("ignore::tendonrod.PlausibilityWarning")

L, R = 0.1, 0.01


def robot(EA=1e5):
    rod = tr.Rod(length=L, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    return tr.Robot(rod, [tr.Tendon(offset=R, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)])


def scene(f, q=R * math.pi / 2 * 0.9, rob=None):
    return tr.Scene(
        rob or robot(),
        displacement=[q, -0.001, -0.001],
        loads=[tr.PointLoad(s=L, force=(0.0, f, 0.0))],
    )


def test_solves_like_tr_solve_cold_then_warm():
    """The first solve is cold and equals tr.solve bitwise; the next one of another load
    starts warm from it (fewer evaluations) and equals tr.solve to the solver tolerance."""
    prob = tr.Problem(scene(0.3))
    a = prob.solve()
    ref = tr.solve(scene(0.3))
    assert a.success and np.array_equal(a.position, ref.position)
    b = prob.solve(scene(0.31))
    cold = tr.solve(scene(0.31))
    assert b.success and b.nfev < cold.nfev
    # both converged to tol 1e-10 (scaled): tips agree to ~1e-9 L
    np.testing.assert_allclose(b.tip_position, cold.tip_position, rtol=0, atol=1e-9 * L)


def test_guess_modes():
    """guess="cold" ignores the kept solution (bitwise a cold solve); a Solution of
    another problem starts from that solution; a bad guess is a ValueError naming it."""
    prob = tr.Problem(scene(0.3))
    prob.solve()
    c = prob.solve(scene(0.2), guess="cold")
    assert np.array_equal(c.position, tr.solve(scene(0.2)).position)
    other = tr.solve(scene(0.21))
    g = prob.solve(scene(0.2), guess=other)
    assert g.success and g.nfev < c.nfev
    with pytest.raises(ValueError, match="guess"):
        prob.solve(guess="warmish")
    with pytest.raises(ValueError, match="guess"):
        prob.solve(guess=np.zeros(3))


@pytest.mark.parametrize(
    "change, field",
    [
        (lambda: scene(0.3, rob=robot(EA=2e5)), "robot.tendons[0].EA"),
        (
            lambda: tr.Scene(
                robot(), tension=[1.0, 0.0, 0.0], loads=[tr.PointLoad(s=L, force=(0, 0.3, 0))]
            ),
            "control kind",
        ),
        (
            lambda: tr.Scene(
                robot(),
                displacement=[0.01, -0.001, -0.001],
                loads=[tr.PointLoad(s=0.05, force=(0, 0.3, 0))],
            ),
            "position",
        ),
        (
            lambda: tr.Scene(
                tr.Robot(
                    tr.Rod(length=0.12, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True),
                    robot().tendons,
                ),
                displacement=[0.01, -0.001, -0.001],
                loads=[tr.PointLoad(s=0.12, force=(0, 0.3, 0))],
            ),
            "robot.rod.length",
        ),
    ],
)
def test_another_structure_is_a_value_error_naming_the_field(change, field):
    prob = tr.Problem(scene(0.3))
    with pytest.raises(ValueError, match=field.replace("[", r"\[").replace("]", r"\]")):
        prob.solve(change())


def test_values_change_without_recompiling():
    """Displacements, loads and pretensions are values: a Problem with pretensioned
    tendons re-solves other pretensions and matches tr.solve of that scene."""
    rod = tr.Rod(length=L, diameter=1.04e-3, E=210e9, G=80e9)

    def pre_scene(p):
        rob = tr.Robot(
            rod,
            [
                tr.Tendon(offset=R, angle=2 * math.pi * i / 3, EA=1e5, pretension=p)
                for i in range(3)
            ],
        )
        return tr.Scene(
            rob, displacement=[0.002, 0.0, 0.0], loads=[tr.PointLoad(s=L, force=(0, 0.1, 0))]
        )

    prob = tr.Problem(pre_scene(1.0))
    prob.solve()
    for p in (2.0, 0.5):
        a = prob.solve(pre_scene(p), guess="cold")
        b = tr.solve(pre_scene(p))
        # the same model values, solved cold: bitwise
        assert np.array_equal(a.tension, b.tension), (p, a.tension, b.tension)


def test_pickle_keeps_scene_and_options_not_the_warm_state():
    prob = tr.Problem(scene(0.3), options=tr.Options(tip_only=True))
    prob.solve()
    back = pickle.loads(pickle.dumps(prob))
    assert back.options == prob.options and back.scene == prob.scene
    assert back.last_solution is None
    assert np.array_equal(
        back.solve().tip_position, tr.solve(scene(0.3), options=prob.options).tip_position
    )


def test_one_thread_at_a_time():
    """A call while another thread is inside a solve of the same Problem raises
    RuntimeError (the workspace is not shared); one Problem per thread works."""
    slow = tr.Options(
        max_work=1e15, max_nfev=10**9, max_continuation=10**6, steps=2000, tip_only=True
    )
    hopeless = tr.Scene(
        robot(),
        displacement=[0.01, -0.002, -0.002],
        loads=[tr.PointLoad(s=L, force=(1e3, 3e2, -1e3))],
    )
    prob = tr.Problem(hopeless, options=slow)
    token = tr._core.Cancel()
    errors = []

    def run():
        from tendonrod._interrupt import cancel_scope

        with cancel_scope(token), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                prob.solve()
            except KeyboardInterrupt:
                errors.append("cancelled")

    t = threading.Thread(target=run)
    t.start()
    try:
        import time

        # wait (no time limit asserted: a loaded machine may start the thread late) until
        # the thread is inside its solve: the workspace's cheap breakpoints query refuses
        while True:
            assert t.is_alive(), errors
            try:
                _ = prob._c.breakpoints
            except RuntimeError:
                break
            time.sleep(0.01)
        with pytest.raises(RuntimeError, match="one thread at a time"):
            prob.solve()
    finally:
        token.set()
        t.join(10)
    assert errors == ["cancelled"]


def test_at_and_compliance_reuse_the_solved_state():
    """Solution.at records from the solution's unknowns without solving (its tip agrees
    with the solution's to the integration accuracy: the nodes split the steps
    differently); Problem.compliance on a spatial problem linearises the kept state and
    equals tr.compliance to its accuracy."""
    prob = tr.Problem(scene(0.3))
    sol = prob.solve()
    st = sol.at(np.array([L / 2, L]))
    # the verified truncation error is <= tol = 1e-10 (scaled by L): 1e-9 L leaves room
    np.testing.assert_allclose(st.position[1], sol.tip_position, rtol=0, atol=1e-9 * L)
    C1 = prob.compliance()
    C2 = tr.compliance(scene(0.3))
    # central differences with step 3e-6 (scaled) give the compliance to ~1e-9 relative
    np.testing.assert_allclose(C1, C2, rtol=0, atol=1e-7 * np.abs(C2).max())


def test_a_scene_used_as_a_guess_elsewhere_keeps_its_structure():
    """A scene that tr.solve already used (and cached facts about) is still recognised as
    the same structure by a Problem: the caches of the two do not collide."""
    sc, near = scene(0.3), scene(0.31)
    g = tr.solve(near)
    tr.solve(sc, guess=g)  # caches the formulation key of both scenes
    prob = tr.Problem(sc)
    assert prob.solve().success and prob.solve(near).success
