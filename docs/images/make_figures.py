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

# the quick start's robot past its critical load: the locked tendon slack (dashed)
wire = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
for f, name in ((0.2, "taut"), (0.5, "slack")):
    load = [tr.PointLoad(s=0.2, force=(0.0, 0.0, -f))]
    sol = tr.solve(tr.Scene(wire, displacement=[0.0157], loads=load))
    ax = tr.plot.robot(sol)
    ax.set_title(
        f"{f} N at the tip: tension {sol.tension[0]:.2f} N, slack {sol.slack[0] * 1e3:.2f} mm"
    )
    ax.figure.savefig(HERE / f"fig17_{name}.png", dpi=90, bbox_inches="tight")
    plt.close("all")

# the friction study (guide/friction.md): the figures of `python -m tendonrod figures`
from tendonrod.paper.figures import figure_registry  # noqa: E402

reg = figure_registry()
for key, name in (("fig25", "friction_band"), ("fig25_hysteresis", "friction_hysteresis")):
    reg[key].make(False).savefig(HERE / f"{name}.png", dpi=80)
