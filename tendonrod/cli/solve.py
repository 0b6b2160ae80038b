"""``tendonrod solve SCENE --out DIR``: solve a scene file and write the solution."""

from __future__ import annotations

import sys
import time

from ._common import EXIT_BAD_INPUT, EXIT_NOT_CONVERGED, EXIT_OK, _read_spec, _require_plot
from ._output import _friction_line, _write_solution


def _cmd_solve(args) -> int:
    import numpy as np

    import tendonrod as tr

    spec = _read_spec("solve", args.scene, args.sliding)
    if spec is None:
        return EXIT_BAD_INPUT
    _require_plot(args)
    t0 = time.perf_counter()
    try:
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", getattr(tr, "ConvergenceWarning", Warning))
            sol = tr.solve(spec.scene, options=spec.options)
    except ValueError as exc:
        print(f"tendonrod solve: error: {args.scene}: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    elapsed = time.perf_counter() - t0
    written = _write_solution(args, spec, sol, elapsed, "solution", {})
    status = "converged" if sol.success else "DID NOT CONVERGE"
    print(
        f"{args.scene}: {status} ({sol.message}); tip at {np.round(sol.tip_position, 6).tolist()} m"
        f"{_friction_line(sol)}; wrote {', '.join(written)} to {args.out}"
    )
    return EXIT_OK if sol.success else EXIT_NOT_CONVERGED
