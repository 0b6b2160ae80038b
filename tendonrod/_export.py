"""A solution written for other tools: :meth:`tendonrod.Solution.export`.

- ``.csv``: one row per output node: s [m]; position x, y, z [m]; the body-to-world rotation
  R11 ... R33 row by row [-]; internal force n_x, n_y, n_z [N]; internal moment m_x, m_y,
  m_z [N m] (all world frame); each tendon's tension at the node [N].  A header line of
  ``#`` comments names the columns with their units (``numpy.loadtxt(path,
  delimiter=",")`` reads it).
- ``.obj`` (Wavefront, text) / ``.stl`` (binary): the backbone as a closed tube at its
  diameter, outward-oriented triangles (see :mod:`tendonrod._mesh`), in metres; with
  ``tendons=True`` each tendon as a thin closed tube too (separate bodies).
- ``.json``: the node arrays, the tip state, tensions, slacks, displacements and the
  solver's verdict, with a ``units`` table.

Nothing here solves; the arrays are the solution's recorded ones.
"""

from __future__ import annotations

import json
import math
import os
import struct

import numpy as np

from ._mesh import Mesh, backbone_radius, backbone_tube, tendon_route, tube

__all__ = ["export", "SUFFIXES"]

SUFFIXES = (".csv", ".obj", ".stl", ".json")


def export(sol, path, *, tendons: bool = False, tendon_diameter=None, sides: int = 32) -> None:
    """Write ``sol`` to ``path``, the format chosen by its suffix (see the module)."""
    p = os.fspath(path)
    suffix = os.path.splitext(p)[1].lower()
    if suffix not in SUFFIXES:
        raise ValueError(f"export: path={p!r} has suffix {suffix!r}; known: {', '.join(SUFFIXES)}")
    if not isinstance(tendons, (bool, np.bool_)):
        raise ValueError(f"tendons must be True or False, got {tendons!r}")
    if suffix == ".csv":
        _csv(sol, p)
    elif suffix == ".json":
        _json(sol, p)
    else:
        mesh = solution_mesh(sol, tendons, tendon_diameter, sides)
        (_obj if suffix == ".obj" else _stl)(mesh, p)


def _columns(sol) -> tuple[list, np.ndarray]:
    nt = np.asarray(sol.tendon_tension).shape[1] if np.ndim(sol.tendon_tension) == 2 else 0
    names = ["s [m]", "x [m]", "y [m]", "z [m]"]
    names += [f"R{i}{j} [-]" for i in (1, 2, 3) for j in (1, 2, 3)]
    names += ["n_x [N]", "n_y [N]", "n_z [N]", "m_x [N m]", "m_y [N m]", "m_z [N m]"]
    names += [f"tension_{i} [N]" for i in range(nt)]
    s = np.asarray(sol.s, dtype=float)
    cols = [
        s[:, None],
        np.asarray(sol.position),
        np.asarray(sol.rotation).reshape(-1, 9),
        np.asarray(sol.force),
        np.asarray(sol.moment),
        np.asarray(sol.tendon_tension).reshape(len(s), nt),
    ]
    return names, np.concatenate(cols, axis=1)


def _csv(sol, p: str) -> None:
    names, table = _columns(sol)
    head = (
        "tendonrod solution: one row per output node, world frame, SI units; "
        "R is the body-to-world rotation row by row\n" + ", ".join(names)
    )
    np.savetxt(p, table, delimiter=",", header=head, fmt="%.17g")


def _json(sol, p: str) -> None:
    def arr(a):
        # NaN (an unconverged solve's unfilled entries) as null: JSON has no NaN
        a = np.asarray(a, dtype=float)
        return np.where(np.isfinite(a), a, None).tolist()

    doc = {
        "format": "tendonrod.solution",
        "frame": "world",
        "units": {
            "s": "m",
            "position": "m",
            "rotation": "-",
            "force": "N",
            "moment": "N m",
            "tendon_tension": "N",
            "tension": "N",
            "slack": "m",
            "displacement": "m",
            "tip_position": "m",
        },
        "success": bool(sol.success),
        "status": int(sol.status),
        "message": str(sol.message),
        "s": arr(sol.s),
        "position": arr(sol.position),
        "rotation": arr(sol.rotation),
        "force": arr(sol.force),
        "moment": arr(sol.moment),
        "tendon_tension": arr(sol.tendon_tension),
        "tension": arr(sol.tension),
        "slack": arr(sol.slack),
        "displacement": arr(sol.displacement),
        "tip_position": arr(sol.tip_position),
        "tip_rotation": arr(sol.tip_rotation),
        "diameter": _diameters(sol),
    }
    with open(p, "w", encoding="utf-8") as fh:
        json.dump(doc, fh, indent=1, allow_nan=False)
        fh.write("\n")


def _diameters(sol) -> list:
    """The backbone's diameter [m] at every node (a segmented rod's per segment)."""
    return (2.0 * backbone_radius(sol.scene, np.asarray(sol.s))).tolist()


def solution_mesh(sol, tendons: bool = False, tendon_diameter=None, sides: int = 32) -> Mesh:
    """The backbone tube (and, with ``tendons``, each tendon's thin tube, of
    ``tendon_diameter`` [m], default a quarter of the backbone's diameter at its base)."""
    scene = sol.scene
    meshes = [backbone_tube(sol, sides)]
    if tendons:
        if tendon_diameter is None:
            rt = 0.25 * float(backbone_radius(scene, [0.0])[0])
        else:
            rt = 0.5 * float(tendon_diameter)
            if not (math.isfinite(rt) and rt > 0):
                raise ValueError(f"tendon_diameter must be > 0 [m], got {tendon_diameter!r}")
        for i in range(scene.robot.n_tendons):
            _, pts = tendon_route(sol, scene, i)
            meshes.append(tube(pts, None, rt, max(8, sides // 4)))
    return Mesh.join(meshes)


def _obj(mesh: Mesh, p: str) -> None:
    with open(p, "w", encoding="ascii") as fh:
        fh.write("# tendonrod backbone tube, metres, outward-oriented triangles\n")
        np.savetxt(fh, mesh.vertices, fmt="v %.17g %.17g %.17g")
        np.savetxt(fh, mesh.faces + 1, fmt="f %d %d %d")


def _stl(mesh: Mesh, p: str) -> None:
    V, F = mesh.vertices, mesh.faces
    tri = V[F].astype(np.float32)
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    norm = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.where(norm > 0, n / np.where(norm > 0, norm, 1.0), 0.0).astype(np.float32)
    rec = np.zeros(len(F), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"], rec["v"] = n, tri
    with open(p, "wb") as fh:
        fh.write(b"tendonrod backbone tube, metres".ljust(80, b" "))
        fh.write(struct.pack("<I", len(F)))
        fh.write(rec.tobytes())
