"""Draw the figures of the user guide (committed PNGs): python docs/images/make_figures.py"""

import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import tendonrod as tr  # noqa: E402

HERE = pathlib.Path(__file__).parent
rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
tendons = [tr.Tendon(offset=0.01, angle=a) for a in (0.0, 2.0944, 4.1888)]
robot = tr.Robot(rod, tendons)
scene = tr.Scene(
    robot,
    tension=[3.0, 0.0, 0.0],  # N, tension control
    loads=[tr.PointLoad(s=0.2, force=(0.0, 0.1, 0.0))],
)
sol = tr.solve(scene)
ax = tr.plot.robot(sol)
ax.figure.savefig(HERE / "three_tendons.png", dpi=110, bbox_inches="tight")
plt.close("all")
