"""The benchmark suites: error against run time (work-precision), the choice of model,
and the stress suite, with the independent references they measure against.

Command line (``python -m tendonrod bench ...``, see :func:`main`)::

    python -m tendonrod bench work-precision --out DIR [--quick]
    python -m tendonrod bench stress --out DIR [--quick] [--timeout SECONDS] [--only SUBSTRING]

- :mod:`~tendonrod.bench.work_precision` -- fixed scenes solved with every integrator
  setting and Jacobian option; relative tip error against an exact or independently
  converged reference, median run time of a cold solve.
- :mod:`~tendonrod.bench.model_choice` -- the closed form (:mod:`tendonrod.analytic`)
  against the Cosserat solver for a straight robot under a growing tip load (Fig. 10).
- :mod:`~tendonrod.bench.stress` (cases in :mod:`~tendonrod.bench.stress_cases` and
  :mod:`~tendonrod.bench.stress_ramps`, checks in :mod:`~tendonrod.bench.verify`) --
  every case in a child process with a timeout: a well-posed case must converge to a
  verified answer, an ill-posed one must fail honestly.
- :mod:`~tendonrod.bench.references`, :mod:`~tendonrod.bench.reference_robot` --
  exact solutions and an independent SciPy solver; they never call the C core.
- :mod:`~tendonrod.bench.common`, :mod:`~tendonrod.bench.plots` -- shared helpers and
  the charts.

Nothing here is timed inside the test suite; the tests import the scene builders and
the verification functions and run small subsets.  (The repository's top-level
``bench/`` directory holds standalone scripts and the committed results.)
"""

from .cli import main

__all__ = ["main"]
