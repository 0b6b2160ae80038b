"""Lazy outputs: a solve computes the tip state, tensions and slacks; the node arrays
are recorded on first access from the solution's unknowns.  They must be bitwise what an
eager solve records (the raw ``_core.solve`` records eagerly), on every scene of the
golden table (every formulation, integrator and option), and reading only the tip must
not record at all."""

from __future__ import annotations

import warnings

import golden_cases as G
import numpy as np
import pytest

import tendonrod as tr
from tendonrod.compiled import _nodes_for, pack_scene

# The golden scenes include absurd loads on purpose (strains far beyond the plausibility
# rules): their PlausibilityWarning is expected here.
pytestmark = pytest.mark.filterwarnings("ignore::tendonrod.PlausibilityWarning")

SCENES = G.scenes()


@pytest.mark.parametrize("name", list(SCENES))
def test_lazy_outputs_equal_the_eager_ones_bitwise(name):
    scene, opts, _ = SCENES[name]
    kw = dict(opts._raw, nodes=_nodes_for(scene, opts))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        eager = tr._core.solve(*pack_scene(scene), **kw)
        lazy = tr.solve(scene, options=opts)
    assert "position" not in lazy.raw  # nothing recorded yet
    for key in ("s", "position", "rotation", "force", "moment", "displacement"):
        got = getattr(lazy, key)
        assert np.array_equal(got, eager[key], equal_nan=True), (name, key)
    for key in ("tension", "slack", "tip_position", "tip_rotation"):
        assert np.array_equal(lazy.raw[key], eager[key], equal_nan=True), (name, key)
    L = scene.robot.rod.length
    if lazy.success and eager["s"][-1] == L:
        # the shooting tip and the recording's last node integrate the same states over
        # step grids that differ only where output nodes split a step: they agree to
        # round-off (1e-9 L leaves room for the integrator's truncation on those splits)
        assert np.allclose(lazy.tip_position, eager["position"][-1], rtol=0, atol=1e-9 * L)


def test_reading_only_the_tip_records_nothing():
    scene, opts, _ = SCENES["spatial_disp_a50"]
    sol = tr.solve(scene, options=opts)
    tip = (sol.tip_position, sol.tip_rotation, sol.tension, sol.slack, sol.displacement)
    assert all(np.isfinite(v).all() for v in tip)
    assert "position" not in sol.raw
    assert sol.position.shape == (len(sol.s), 3)
    assert "position" in sol.raw
