"""Fixed step counts carry an error estimate: with ``Options(steps=N)`` the core reports
the step-doubling estimate of the truncation error (the one the automatic step count is
verified with: the change of the residual and of the scaled tip state when every
segment's steps are doubled, over 1 - 2^-p), and a converged solve whose estimate is
above TR_FIXED_TRUNC_WARN (1e4) x tol warns.  The reference is the automatic-step solve
of the same scene, verified to a truncation estimate below tol (1e-10)."""

import math
import warnings

import numpy as np
import pytest

import tendonrod as tr

L = 0.2


def _scene():
    # the README's robot retracted r pi (a 180 deg bend) with an out-of-plane tip load
    rod = tr.Rod(length=L, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    return tr.Scene(
        robot,
        displacement=[0.01 * math.pi],
        loads=[tr.PointLoad(s=L, force=(0.05, 0.02, -0.05))],
    )


@pytest.fixture(scope="module")
def reference():
    sol = tr.solve(_scene())
    assert sol.success and sol.truncation_estimate <= 1e-10, sol.message
    return sol


@pytest.mark.parametrize(("integrator", "steps"), [("rk4", 4), ("rk4", 8), ("rk8", 2)])
def test_coarse_fixed_steps_estimate_their_error_and_warn(reference, integrator, steps):
    with pytest.warns(tr.ConvergenceWarning, match="truncation error at the fixed"):
        sol = tr.solve(_scene(), options=tr.Options(steps=steps, integrator=integrator))
    assert sol.success, sol.message
    err = np.max(np.abs(sol.tip_position - reference.tip_position)) / L
    est = sol.truncation_estimate
    # the true tip error (scaled by L) is 2.8e-3, 2.1e-4, 2.4e-6 here, and the reference
    # is 1e6x more accurate; step doubling measured 2.5-3.1x above it.  It must not
    # under-report by more than 2x (the doubled solve's own error is 2^-p of it, and the
    # estimate is a max-norm over residual and tip state where the error is one
    # component), nor over-report by more than 10x (it would then be no estimate)
    assert err / 2 <= est <= 10 * err, (est, err)


def test_fine_fixed_steps_report_a_small_estimate_without_warning(reference):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sol = tr.solve(_scene(), options=tr.Options(steps=16, integrator="rk8"))
    assert sol.success and sol.status == 0, sol.message
    # rk8 at 16 steps: ~1e-12 scaled, far below 1e4 tol (the warning threshold) and
    # at the reference's own accuracy (its estimate <= tol 1e-10)
    assert 0 < sol.truncation_estimate <= 1e-10, sol.truncation_estimate
    assert np.max(np.abs(sol.tip_position - reference.tip_position)) / L <= 1e-9
