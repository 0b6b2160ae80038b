"""The automatic initial step count reads the tendons' curling, not only the external
loads: a tension-driven robot curled ~1,580 deg solves warm after a 1e-8 N nudge (a new
point load, so the guess's verified step count does not carry) at a step count
comparable to the unloaded one; before, the count fell to the 2 rk8 steps a 1e-8 N load
alone asks for and the solve failed with its tip 2e5 m away."""

import warnings

import numpy as np

import tendonrod as tr


def _robot():
    rod = tr.Rod(
        length=0.24858828448153775,
        diameter=0.0005432589400486138,
        E=178321767483.08188,
        G=68585295185.80072,
    )
    return tr.Robot(
        rod,
        [
            tr.Tendon(offset=0.007981634563834425, angle=0.7469654859933543, EA=37067.923305631346),
            tr.Tendon(
                offset=0.006959739633198718,
                angle=0.08577690908448624,
                EA=22572.83039553928,
                end=0.16453072187481868,
            ),
        ],
    )


T = [6.959393744468623, 6.284329104616425]


def test_a_tiny_load_does_not_collapse_the_step_count():
    robot = _robot()
    L = robot.rod.length
    # the scene is extreme on purpose: its plausibility warnings (a tendon near the
    # centre of curvature, the curl) are expected; a ConvergenceWarning is not
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.PlausibilityWarning)
        sol0 = tr.solve(tr.Scene(robot, tension=T), strict=True)
    # the tensions curl the rod tau r l / EI = 27.5 rad (1,580 deg) in all
    EI = robot.rod.bending_stiffness
    turn = T[0] * 0.007981634563834425 * L / EI + T[1] * 0.006959739633198718 * 0.16453 / EI
    assert turn > 27, turn
    nudged = tr.Scene(robot, tension=T, loads=[tr.PointLoad(s=L, force=(1e-8, 0.0, 0.0))])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.PlausibilityWarning)
        warnings.simplefilter("error", tr.ConvergenceWarning)
        sol = tr.solve(nudged, guess=sol0, strict=True)
    assert sol.success and sol.truncation_estimate <= 1e-10, sol.message
    # a step count of the unloaded one's order (both verified to tol: within 2x)
    n0, n = sol0.formulation.steps, sol.formulation.steps
    assert n0 / 2 <= n <= 2 * n0, (n0, n)
    # 1e-8 N moves the tip by far less than a micrometre (the compliance of a 0.25 m
    # rod of EI 7.6e-4 N m^2 is ~L^3 / 3 EI = 7 m/N at most: 7e-8 m)
    assert np.linalg.norm(sol.tip_position - sol0.tip_position) < 1e-6
