"""Draw the model page's figure of frames, a tendon's route and the signs (committed PNG):

    python docs/images/make_model_frames.py        # writes docs/images/model_frames.png

The bent robot is a solution of tendonrod itself (a converging tendon at +x pulled with
2 N, a dead tip load), so the signs drawn are the solver's: retracting the tendon at
phi = 0 turns the tip from +z toward +x (theta > 0).
"""

import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Arc, Circle  # noqa: E402

import tendonrod as tr  # noqa: E402

HERE = pathlib.Path(__file__).parent
L, b = 0.2, 0.02  # m: rod length, the tendon's base offset (large, to be visible)
rod = tr.Rod(length=L, diameter=1.5e-3, E=200e9, G=80e9, kirchhoff=True)
tendon = tr.Tendon.converging(offset=b, length=L)  # r(s) = (a s + b) e1, a = -b/L
F = (-0.5, 0.0, 0.0)  # N, world: the closed forms' F > 0 (it points away from the tendon)
sol = tr.solve(
    tr.Scene(tr.Robot(rod, [tendon]), tension=[40.0], loads=[tr.PointLoad(s=L, force=F)])
)
p, R, s = sol.position, sol.rotation, sol.s
r_body = np.outer(tendon.offset + tendon.slope * s, [1.0, 0.0, 0.0])  # (N, 3), body frame
route = p + np.einsum("nij,nj->ni", R, r_body)  # the tendon in the world frame

plt.rcParams.update({"font.size": 10, "mathtext.fontset": "dejavusans"})
fig, (ax, bx) = plt.subplots(1, 2, figsize=(10.5, 5.4), gridspec_kw={"width_ratios": [1.7, 1]})


def arrow(ax, start, vec, color, label=None, off=(0.004, 0.004), **kw):
    ax.annotate(
        "",
        xy=(start[0] + vec[0], start[1] + vec[1]),
        xytext=start,
        arrowprops=dict(arrowstyle="-|>", color=color, lw=1.6, shrinkA=0, shrinkB=0),
    )
    if label:
        ax.text(start[0] + vec[0] + off[0], start[1] + vec[1] + off[1], label, color=color, **kw)


# (a) side view, the x-z plane of the world
ax.plot([0, 0], [0, L], color="0.6", ls="--", lw=1)
ax.text(-0.058, 0.6 * L, "undeformed rod\n(along $+z$)", color="0.45", fontsize=8)
ax.plot(p[:, 0], p[:, 2], color="k", lw=3, label="backbone $p(s)$")
ax.plot(route[:, 0], route[:, 2], color="tab:red", lw=1.4, label="tendon $p + R\\,r(s)$")
for k in range(0, len(s), 10):  # the channel's guides: the offset r(s) drawn in the section
    ax.plot([p[k, 0], route[k, 0]], [p[k, 2], route[k, 2]], color="tab:red", lw=0.6, alpha=0.6)
ax.plot(*route[-1, [0, 2]], "o", color="tab:red", ms=5)
ax.text(route[-1, 0] + 0.004, route[-1, 2] - 0.01, "anchor $s = t$", color="tab:red", fontsize=8)
# world frame at the clamped base
arrow(ax, (0, 0), (0.04, 0), "tab:blue", "$x$ (world)", off=(0.003, -0.008))
arrow(ax, (0, 0), (0, 0.04), "tab:blue", "$z$", off=(0.004, -0.004))
ax.add_patch(plt.Rectangle((-0.035, -0.012), 0.07, 0.012, hatch="////", fill=False, lw=0.8))
ax.text(-0.058, -0.04, "clamped base, $s = 0$:\nbase frame = world frame", fontsize=8)
# body frame d1, d3 at s = 0.6 L
k = int(0.5 * (len(s) - 1))
for col, name, off in ((0, "$R e_1$", (0.006, -0.008)), (2, "$R e_3$", (-0.012, 0.004))):
    v = 0.035 * R[k][:, col]
    arrow(ax, (p[k, 0], p[k, 2]), (v[0], v[2]), "tab:green", name, off=off)
ax.text(p[k, 0] - 0.045, p[k, 2] - 0.05, "body frame $R(s)$", color="tab:green", fontsize=8)
# the tip angle theta, from +z toward +x
tip = p[-1, [0, 2]]
theta = math.atan2(R[-1][0, 2], R[-1][2, 2])
ax.plot([tip[0], tip[0]], [tip[1], tip[1] + 0.04], color="0.4", lw=0.8, ls=":")
t3 = R[-1][:, 2]
ax.plot([tip[0], tip[0] + 0.04 * t3[0]], [tip[1], tip[1] + 0.04 * t3[2]], color="0.4", lw=0.8)
ax.add_patch(Arc(tip, 0.05, 0.05, theta1=90 - math.degrees(theta), theta2=90, color="0.2", lw=1))
ax.text(tip[0] + 0.006, tip[1] + 0.03, f"$\\theta_L = {math.degrees(theta):.0f}°$ > 0", fontsize=9)
# the tip load, world frame
arrow(ax, (tip[0], tip[1] - 0.02), (-0.035, 0), "tab:purple", None)
ax.text(
    tip[0] - 0.055,
    tip[1] - 0.045,
    "$-F e_x$ ($F > 0$ in the\nclosed forms)",
    color="tab:purple",
    fontsize=8,
)
# the actuator: q > 0 retracts the tendon at the base
arrow(ax, (b, -0.004), (0, -0.025), "tab:red", "$q > 0$ retracts", off=(0.004, 0.0), fontsize=8)
ax.text(b + 0.004, 0.006, "$\\tau \\geq 0$ uniform\n(no friction)", color="tab:red", fontsize=8)
# internal force and moment at a cut
kc = int(0.3 * (len(s) - 1))
ax.plot(*p[kc, [0, 2]], "s", color="tab:orange", ms=5)
ax.text(
    -0.06,
    0.03,
    "$n(s), m(s)$ at a cut:\ndistal on proximal,\nbackbone only",
    color="tab:orange",
    fontsize=8,
)
ax.set(xlabel="x [m]", ylabel="z [m]", title="(a) side view: frames, route, signs")
ax.set_aspect("equal")
ax.set_xlim(-0.065, 0.2)
ax.set_ylim(-0.05, 0.15)
ax.legend(loc="upper right", fontsize=8, frameon=False)

# (b) the cross-section seen from the tip (e3 toward the viewer):
# e1 to the right, e2 up; tendon i at angle phi_i from d1 toward d2, radius a_i s + b_i
bx.add_patch(Circle((0, 0), 1.0, fill=False, color="0.5", ls="--", lw=0.8))
bx.add_patch(Circle((0, 0), 0.12, color="k"))
arrow(bx, (0, 0), (1.35, 0), "tab:green", "$e_1$", off=(0.04, -0.03))
arrow(bx, (0, 0), (0, 1.35), "tab:green", "$e_2$", off=(0.04, 0.0))
bx.text(-0.2, -0.25, "$e_3$ (out of\nthe page)", color="tab:green", fontsize=8, ha="right")
for i, phi in enumerate((0.0, 2 * math.pi / 3, 4 * math.pi / 3)):
    c = ("tab:red", "tab:gray", "tab:gray")[i]
    bx.plot(math.cos(phi), math.sin(phi), "o", color=c, ms=9)
    bx.text(
        1.2 * math.cos(phi) - 0.25,
        1.2 * math.sin(phi) + (0.1 if i < 2 else -0.22),
        f"$\\phi_{i} = {round(math.degrees(phi))}°$",
        fontsize=9,
        color=c,
    )
bx.add_patch(Arc((0, 0), 0.9, 0.9, theta1=0, theta2=120, color="0.2", lw=1))
bx.annotate(
    "",
    xy=(-0.225, 0.39),
    xytext=(-0.15, 0.42),
    arrowprops=dict(arrowstyle="-|>", color="0.2", lw=1),
)
bx.text(0.32, 0.42, "$\\phi$", fontsize=11)
bx.plot([0, math.cos(4 * math.pi / 3)], [0, math.sin(4 * math.pi / 3)], color="0.3", lw=0.8)
bx.text(-0.3, -0.45, "$r_i(s) = a_i s + b_i$", fontsize=9, ha="right")
bx.text(
    -1.55,
    -1.55,
    "retracting the tendon at $\\phi = 0$ bends\nthe rod toward body $+e_1$ (world $+x$ when straight): $\\theta > 0$",
    fontsize=8,
)
bx.set_aspect("equal")
bx.set_xlim(-1.6, 1.7)
bx.set_ylim(-1.65, 1.6)
bx.axis("off")
bx.set_title("(b) cross-section, body frame")
fig.tight_layout()
fig.savefig(HERE / "model_frames.png", dpi=110, metadata={"Software": None})
print("wrote", HERE / "model_frames.png", f"(theta_L = {math.degrees(theta):.1f} deg)")
