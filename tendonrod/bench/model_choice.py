"""Choice of model: the paper's closed form against the Cosserat solver.

Paper Fig. 10: the straight robot (Fig. 17 robot, one parallel tendon at q = 0)
under a growing transverse tip load.  Records the error of the closed form as the
library ships it (:func:`tendonrod.analytic.deflection`, eq. 26 at the tip) against
the Cosserat answer, beside the run time of each.  Writes ``DIR/model_choice.csv``
and ``DIR/model_choice.png``.
"""

from __future__ import annotations

import math
import os
import time

import numpy as np

from .. import analytic
from ..model import PointLoad, Robot, Scene, Tendon
from ..options import Options
from . import references as refs
from .common import FIG17, EI_of, rod_of, solve_quiet, time_solve, write_csv
from .plots import plot_model_choice

__all__ = ["run_model_choice", "MODEL_CHOICE_COLS"]

MODEL_CHOICE_COLS = [
    "model",
    "load",
    "force",
    "closed_form",
    "cosserat",
    "error",
    "seconds_closed_scalar",
    "seconds_closed_vector",
    "seconds_cosserat_cold",
    "seconds_cosserat_warm",
    "cosserat_success",
    "default_error",
    "cosserat_vs_exact",
]
"""The columns of ``model_choice.csv``."""


def run_model_choice(out: str, quick: bool = False, log=print):
    """Paper Fig. 10: straight robot (Fig. 17 robot, one parallel tendon at q = 0)
    under a growing transverse tip load; error of the closed form (eq. 26 at the
    tip) against the Cosserat solution, beside the run time of each."""
    os.makedirs(out, exist_ok=True)
    p = FIG17
    L, EI, r = p["L"], EI_of(p), p["r"]
    loads = np.logspace(-3, 2, 11 if quick else 26)  # F L^2 / EI
    variants = [("no tendon", None), ("tendon r²kL/EI = 1", 1.0), ("inextensible tendon", math.inf)]
    # The comparison is in the plane, as the closed forms are: the planar equilibrium is
    # the answer of record even where it is unstable out of the plane (the robot with a
    # locked inextensible tendon buckles laterally from F L^2/EI ~ 10), so every solve
    # here accepts unstable equilibria.
    ref_opts = Options(
        integrator="rk8", steps=256, tol=1e-11, accept_unstable=True
    )  # fine enough at F L^2/EI = 100
    planar = Options(accept_unstable=True)
    cf_name = "tr.analytic.deflection"
    rows = []
    for name, alpha in variants:
        if alpha is None:
            robot = Robot(rod_of(p), [])
            k = 0.0
        else:
            EA = math.inf if math.isinf(alpha) else alpha * EI / r**2
            k = EA / L
            robot = Robot(rod_of(p), [Tendon(offset=r, EA=EA)])
        prev = None
        for fl in loads:
            F = fl * EI / L**2
            disp = None if alpha is None else [0.0]
            sc = Scene(robot, displacement=disp, loads=[PointLoad(s=L, force=(-F, 0.0, 0.0))])
            d_cf, t_cf, t_vec = _time_closed_form(L, F, EI, r, k)
            t_cold, sol = time_solve(sc, planar, 3 if quick else 7)
            t_warm = math.nan
            if prev is not None:
                t_warm, _ = time_solve(sc, planar, 3 if quick else 7, guess=prev)
            ref = _answer_of_record(sc, robot, disp, prev, F, ref_opts, L)
            if ref is None:
                log(
                    f"  {name}: F L^2/EI = {fl:.3g}: warm-started solve left the loading path; dropped"
                )
                rows.append(
                    dict(
                        model=name,
                        load=fl,
                        force=F,
                        closed_form=d_cf,
                        cosserat=math.nan,
                        error=math.nan,
                        cosserat_vs_exact=math.nan,
                        seconds_closed_scalar=t_cf,
                        seconds_closed_vector=t_vec,
                        seconds_cosserat_cold=t_cold,
                        seconds_cosserat_warm=math.nan,
                        cosserat_success=False,
                        default_error=math.nan,
                    )
                )
                continue
            if ref.success:
                prev = ref
            x = -ref.tip_position[0]
            err = abs(d_cf - x) / abs(x) if ref.success else math.nan
            exact = math.nan
            if alpha is None:  # no tendon: the exact elastica checks the answer of record
                xe, ze, _ = refs.elastica_tip_force(L, EI, F)
                exact = float(np.hypot(ref.tip_position[0] + xe, ref.tip_position[2] - ze) / L)
            rows.append(
                dict(
                    model=name,
                    load=fl,
                    force=F,
                    closed_form=d_cf,
                    cosserat=x,
                    error=err,
                    cosserat_vs_exact=exact,
                    seconds_closed_scalar=t_cf,
                    seconds_closed_vector=t_vec,
                    seconds_cosserat_cold=t_cold,
                    seconds_cosserat_warm=t_warm,
                    cosserat_success=bool(ref.success),
                    default_error=(
                        float(np.linalg.norm(sol.tip_position - ref.tip_position)) / L
                        if sol.success
                        else math.nan
                    ),
                )
            )
            log(
                f"  {name:22s} FL²/EI={fl:8.3g}: closed-form error {err:.2e}; closed {t_cf * 1e6:.2f} µs, "
                f"Cosserat cold {t_cold * 1e3:.3f} ms warm {t_warm * 1e3:.3f} ms"
            )
    write_csv(os.path.join(out, "model_choice.csv"), rows, MODEL_CHOICE_COLS)
    plot_model_choice(rows, os.path.join(out, "model_choice.png"), cf_name)
    return rows


def _time_closed_form(L, F, EI, r, k):
    """``(tip deflection, seconds per scalar call, seconds per point of a 10^4 array)``
    of the closed form: the scalar call timed as the median of many, then vectorised."""
    reps = 200
    t0 = time.perf_counter()
    for _ in range(reps):
        d_cf = float(analytic.deflection(L, F, L, L, EI, 0.0, r, k))
    t_cf = (time.perf_counter() - t0) / reps
    vec = np.full(10000, F)
    t0 = time.perf_counter()
    analytic.deflection(L, vec, L, L, EI, 0.0, r, k)
    t_vec = (time.perf_counter() - t0) / vec.size
    return d_cf, t_cf, t_vec


def _answer_of_record(sc, robot, disp, prev, F, ref_opts, L):
    """The Cosserat answer of record at tip load ``F``, or None if the warm-started
    path left the loading path (another equilibrium).

    It follows the loading path: warm started from the previous (smaller) load's
    answer ``prev``, never from a cold solve, which can land on another, unstable
    equilibrium at large loads."""
    if prev is None:
        return solve_quiet(sc, ref_opts)
    # sub-steps of at most 10 % in load: a 58 % step from a warm start already
    # jumps to another branch at F L^2/EI ~ 40-60
    f_prev = -prev.scene.point_loads[0].force[0]
    nsub = max(1, int(math.ceil(math.log(F / f_prev) / math.log(1.1))))
    ref = prev
    for Fk in np.geomspace(f_prev, F, nsub + 1)[1:]:
        sck = Scene(robot, displacement=disp, loads=[PointLoad(s=L, force=(-Fk, 0.0, 0.0))])
        last = ref
        ref = solve_quiet(sck, ref_opts, guess=ref)
        if not ref.success:
            break
        # a 10 % load step moves the tip by a few % of L at most; more means the
        # warm-started solve jumped to another equilibrium
        if np.linalg.norm(ref.tip_position - last.tip_position) > 0.05 * L:
            return None
    return ref
