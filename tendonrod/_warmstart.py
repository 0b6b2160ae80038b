"""How a warm start maps to the core's guess: a :class:`~tendonrod.Solution` (its base
state, and where the compiled structure is the same its Jacobian, step verification and
stability carry) or an array ``[n(0), m(0), tension, slack]`` (world frame for a mounted
robot), into what ``_core.Problem.solve`` takes."""

from __future__ import annotations

import numpy as np

from .compiled import _structure_key, structure_difference
from .model import Scene
from .mounting import base_pose, vectors_in
from .options import Options
from .solution import Solution

# Options that fix the layout and scaling of the unknowns and what a step verification
# measured: a verification record carries between solves that agree on them (and on the
# scene's structure, which fixes the scales).
_VERIFICATION_OPTIONS = ("integrator", "shooting_segments", "force_spatial", "slack_model")


def _verification_of(guess: Solution, scene: Scene, options: Options):
    """``(steps, estimate, unknowns, values)`` of the step verification that vouches for the
    solution ``guess``, when it can carry to a solve of ``scene`` with ``options`` (same
    compiled structure and unknowns); else None."""
    xv = guess._get("verified_unknowns")
    if xv is None or guess.scene is None or options.steps != 0:
        return None
    if any(getattr(guess.options, f) != getattr(options, f) for f in _VERIFICATION_OPTIONS):
        return None
    if structure_difference(guess.scene, scene, options.force_spatial) is not None:
        return None
    return (
        int(guess._get("formulation")["steps"]),
        float(guess._get("verified_estimate")),
        xv,
        guess._get("verified_values"),
    )


def _guess_vector(guess, scene: Scene, options: Options):
    """(guess array (6+2nt,) or None, jacobian or None, verification record or None,
    stability verdict record or None) from a Solution or an array."""
    nt = scene.robot.n_tendons
    if guess is None:
        return None, None, None, None
    if isinstance(guess, Solution):
        if guess.tension.shape != (nt,):
            raise ValueError(
                f"guess: a Solution with {guess.tension.shape[0]} tendons cannot "
                f"start a scene with {nt} tendons"
            )
        vec = guess._get("base_state")  # base frame, as the core takes it
        jac = carry = None
        if guess.scene is not None and _structure_key(guess.scene, guess.options) == _structure_key(
            scene, options
        ):
            # the same compiled structure: the same unknowns, scales and values
            jac = guess.jacobian
            carry = guess._get("stability_carry")
        if not np.all(np.isfinite(vec)):
            return None, None, None, None
        return vec, jac, _verification_of(guess, scene, options), carry
    try:
        vec = np.array(guess, dtype=float).ravel()
    except (TypeError, ValueError, OverflowError):
        raise ValueError(
            f"guess must be None, a Solution or an array of shape ({6 + 2 * nt},), got {guess!r}"
        ) from None
    if vec.shape != (6 + 2 * nt,) or not np.all(np.isfinite(vec)):
        raise ValueError(
            f"guess must be a finite array of shape ({6 + 2 * nt},) "
            f"[n(0), m(0), tension, slack], got {guess!r}"
        )
    pose = base_pose(scene.robot)
    if pose is not None:  # n(0), m(0) given in the world frame
        vec = np.concatenate([vectors_in(pose, vec[:3]), vectors_in(pose, vec[3:6]), vec[6:]])
    return vec, None, None, None
