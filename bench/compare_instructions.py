"""Instructions per solve of two builds, counted by callgrind: a machine-independent check.

Timings on these shared machines drift by tens of percent; an instruction count does
not.  For each build (a checkout with its extension built in place, as for
``bench/compare_builds.py``) and each scene, the same script runs under
``valgrind --tool=callgrind`` twice, with n1 and n2 solves after the imports; the
difference of the two totals over n2 - n1 is the count of one solve, imports and
start-up excluded.  OpenBLAS is held to one thread (its idle threads spin, and callgrind
counts the spinning).  Scenes: the Fig. 11c robot (spatial, three extensible tendons,
out-of-plane load) and the Fig. 17 robot (planar, one tendon, a tip load), both
frictionless, cold ``tr.solve`` with default options; the latter also as a Cosserat rod
with EA = 3e3 N tendons.

    .venv/bin/python bench/compare_instructions.py --old /path/to/old/checkout

Prints a table (instructions per solve, new/old); writes nothing.  About 2 minutes.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
NEW = os.path.dirname(HERE)

SCENES = {
    "fig11c cold": r"""
rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
EI, L, r = rod.bending_stiffness, rod.length, 0.01
EA = 50.0 * 3 * EI / r**2
robot = tr.Robot(rod, [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)])
q = [r * math.pi / 2 * 0.98, -0.001, -0.001]
sc = tr.Scene(robot, displacement=q, loads=[tr.PointLoad(s=L, force=(0, 0.5, 0))])
""",
    "fig17 planar cold": r"""
rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
robot = tr.Robot(rod, [tr.Tendon(offset=0.01)])
sc = tr.Scene(robot, displacement=[0.015], loads=[tr.PointLoad(s=0.2, force=(0, 0, -0.2))])
""",
    "fig17 cosserat cold": r"""
rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=False)
robot = tr.Robot(rod, [tr.Tendon(offset=0.01, EA=3e3)])
sc = tr.Scene(robot, displacement=[0.015], loads=[tr.PointLoad(s=0.2, force=(0, 0, -0.2))])
""",
}


def count(checkout: str, scene: str, n: int) -> int:
    body = (
        "import math\nimport tendonrod as tr\n" + scene + f"\nfor _ in range({n}): tr.solve(sc)\n"
    )
    env = dict(os.environ, PYTHONPATH=checkout, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    with tempfile.TemporaryDirectory() as tmp:
        script, out = os.path.join(tmp, "s.py"), os.path.join(tmp, "cg.out")
        with open(script, "w") as fh:
            fh.write(body)
        subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", sys.executable, script],
            env=env,
            check=True,
            capture_output=True,
            cwd="/",
        )
        text = subprocess.run(
            ["callgrind_annotate", out], capture_output=True, text=True, check=True
        ).stdout
    m = re.search(r"([\d,]+)\s+\([\s\d.]+%\)\s+PROGRAM TOTALS", text)
    return int(m.group(1).replace(",", ""))


def per_solve(checkout: str, scene: str, n1: int, n2: int) -> float:
    return (count(checkout, scene, n2) - count(checkout, scene, n1)) / (n2 - n1)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, help="checkout of the old build (built in place)")
    ap.add_argument("--new", default=NEW, help="checkout of the new build (default: this one)")
    ap.add_argument("--n1", type=int, default=10)
    ap.add_argument("--n2", type=int, default=50)
    args = ap.parse_args(argv)
    print(f"{'scene':20s} {'old':>12s} {'new':>12s} {'new/old':>8s}   (instructions per solve)")
    for name, scene in SCENES.items():
        old = per_solve(args.old, scene, args.n1, args.n2)
        new = per_solve(args.new, scene, args.n1, args.n2)
        print(f"{name:20s} {old:12.0f} {new:12.0f} {new / old:8.4f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
