"""``tendonrod solve SCENE --out DIR``: solve a scene file and write the solution."""

from __future__ import annotations

import sys
import time

from ._common import EXIT_BAD_INPUT, EXIT_NOT_CONVERGED, EXIT_OK, _require_plot, _with_sliding
from ._output import _friction_line, _write_solution


def _cmd_solve(args) -> int:
    import numpy as np

    import tendonrod as tr
    from tendonrod.scenefile import SceneFileError, load_scene

    try:
        spec = load_scene(args.scene)
    except SceneFileError as exc:
        print(f"tendonrod solve: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as exc:
        print(
            f"tendonrod solve: error: cannot read scene file {args.scene!r}: {exc.strerror or exc}",
            file=sys.stderr,
        )
        return EXIT_BAD_INPUT
    spec = _with_sliding(spec, args.sliding)
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
