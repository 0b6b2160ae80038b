"""Plotting helpers (matplotlib, imported inside each function).

Every function takes ``ax=None`` (None: the current Axes of pyplot, or a new
3D Axes where one is needed), draws, labels the axes with units or as the
nondimensional group, and returns the Axes.  Nothing here calls
``plt.show()`` or ``savefig``.

- :func:`robot` -- the solved robot: backbone, tendons along their routes
  r(s) mapped through the solved frames, spacer disks, point loads as arrows;
  a 3D view, or the x-z plane for planar scenes.
- :func:`shapes` -- several backbones in the x-z plane (deflection curves).
- :func:`sweep_lines` -- a recorded quantity of a sweep against one varied parameter.
- Charts: :func:`sigma_vs_zeta` (Figs. 3, 6), :func:`tip_sigma_vs_alpha`
  (Fig. 7), :func:`compliance_map` (Figs. 13-15), :func:`tip_compliance_vs_alpha`
  (Fig. 16), :func:`tension_vs_load` (Figs. 17-18), :func:`torsion` (Fig. 12),
  :func:`straight_load` (Fig. 10), :func:`prototype_deflection`,
  :func:`prototype_tension`, :func:`prototype_shapes` (Figs. 20-23).
- :func:`paper_figures` -- the list the ``figures`` command renders.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "is_planar",
    "robot",
    "shapes",
    "sweep_lines",
    "sigma_vs_zeta",
    "tip_sigma_vs_alpha",
    "compliance_map",
    "tip_compliance_vs_alpha",
    "tension_vs_load",
    "torsion",
    "straight_load",
    "prototype_deflection",
    "prototype_tension",
    "prototype_shapes",
    "paper_figures",
]

SIGMA_LABEL = r"$\sigma = 12\,EI\,\delta\,/\,(F L^3)$"
ZETA_LABEL = r"$\zeta = z / L$"
ALPHA_LABEL = r"$r^2 k L\,/\,EI$"


def _ax(ax, projection=None):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    if projection is None:
        return plt.gca()
    return plt.figure().add_subplot(projection=projection)


def is_planar(scene) -> bool:
    """True when every tendon lies at angle 0 or pi and every load in the x-z plane
    (forces without y, moments about y only): the solution stays in the x-z plane."""
    for t in scene.robot.tendons:
        if abs(math.sin(t.angle)) > 1e-12 and (t.offset != 0.0 or t.slope != 0.0):
            return False
    for ld in scene.loads:
        f = np.asarray(ld.force, dtype=float)
        m = np.asarray(getattr(ld, "moment", (0.0, 0.0, 0.0)), dtype=float)
        if f[1] != 0.0 or m[0] != 0.0 or m[2] != 0.0:
            return False
    return True


def _state_at(sol, s):
    """Positions (K, 3) and rotations (K, 3, 3) at arc lengths s, interpolated between
    output nodes (positions linearly, rotations per column then re-orthonormalised) --
    enough for drawing."""
    s = np.atleast_1d(np.asarray(s, dtype=float))
    ss = np.asarray(sol.s)
    P = np.stack([np.interp(s, ss, np.asarray(sol.position)[:, j]) for j in range(3)], axis=-1)
    Rn = np.asarray(sol.rotation)
    R = np.empty((len(s), 3, 3))
    for i in range(3):
        for j in range(3):
            R[:, i, j] = np.interp(s, ss, Rn[:, i, j])
    u, _, vt = np.linalg.svd(R)
    return P, u @ vt


def robot(
    sol,
    scene=None,
    ax=None,
    planar=None,
    disks: int = 8,
    disk_radius=None,
    tendons: bool = True,
    loads: bool = True,
    load_scale=None,
    color="k",
    label=None,
    alpha: float = 1.0,
):
    """Draw a solved robot.

    Parameters
    ----------
    sol : tendonrod.Solution
    scene : tendonrod.Scene, optional
        Default ``sol.scene``.
    ax : Axes, optional
        A 3D Axes (spatial view) or 2D Axes (x-z view).  None: 2D for planar
        scenes, else a new 3D Axes.
    planar : bool, optional
        Force the x-z view (True) or the 3D view (False); default from ``ax`` or
        :func:`is_planar`.
    disks : int
        Spacer disks drawn at evenly spaced arc lengths (0: none).
    disk_radius : float, optional
        [m], default 1.3 times the largest tendon offset (or L/30 without tendons).
    loads : bool
        Point loads as arrows (length ``load_scale`` [m/N], default: the largest
        force drawn L/4 long).
    """
    scene = getattr(sol, "scene", None) if scene is None else scene
    if scene is None:
        raise ValueError("robot(): pass scene= (the solution does not carry its scene)")
    if ax is not None:
        is3d = getattr(ax, "name", "") == "3d"
        planar = (not is3d) if planar is None else planar
    else:
        planar = is_planar(scene) if planar is None else planar
        ax = _ax(None, None if planar else "3d")
    L = scene.robot.rod.length
    P = np.asarray(sol.position)

    def draw(pts, **kw):
        pts = np.asarray(pts)
        if planar:
            return ax.plot(pts[:, 0], pts[:, 2], **kw)
        return ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], **kw)

    draw(P, color=color, lw=2.0, label=label, alpha=alpha)
    offsets = [t.offset for t in scene.robot.tendons]
    rad = (
        disk_radius
        if disk_radius is not None
        else (1.3 * max(offsets) if offsets and max(offsets) > 0 else L / 30)
    )
    tcolors = ["tab:red", "tab:blue", "tab:green", "tab:orange", "tab:purple", "tab:brown"]
    if tendons:
        for i, t in enumerate(scene.robot.tendons):
            end = scene.robot.tendon_end(i)
            s = np.linspace(0.0, end, 60)
            Ps, Rs = _state_at(sol, s)
            r = (t.slope * s + t.offset)[:, None] * np.array(
                [math.cos(t.angle), math.sin(t.angle), 0.0]
            )
            draw(
                Ps + np.einsum("kij,kj->ki", Rs, r),
                color=tcolors[i % len(tcolors)],
                lw=1.0,
                alpha=alpha,
            )
    if disks:
        sd = np.linspace(0.0, L, disks + 1)[1:]
        Ps, Rs = _state_at(sol, sd)
        ang = np.linspace(0.0, 2 * math.pi, 33)
        ring = rad * np.stack([np.cos(ang), np.sin(ang), np.zeros_like(ang)], axis=-1)
        for p, R in zip(Ps, Rs):
            if planar:
                ends = p + np.array([R @ np.array([-rad, 0, 0]), R @ np.array([rad, 0, 0])])
                draw(ends, color="0.5", lw=1.5, alpha=alpha)
            else:
                draw(p + ring @ R.T, color="0.5", lw=0.8, alpha=alpha)
    if loads:
        pls = [ld for ld in scene.loads if hasattr(ld, "s")]
        fmax = max([np.linalg.norm(ld.force) for ld in pls] + [0.0])
        scale = load_scale if load_scale is not None else (0.25 * L / fmax if fmax > 0 else 0.0)
        for ld in pls:
            f = np.asarray(ld.force, dtype=float)
            if not np.any(f) or scale == 0.0:
                continue
            p, _ = _state_at(sol, [ld.s])
            p = p[0]
            v = f * scale
            if planar:
                ax.annotate(
                    "",
                    xy=(p[0], p[2]),
                    xytext=(p[0] - v[0], p[2] - v[2]),
                    arrowprops=dict(arrowstyle="->", color="tab:purple", lw=1.5),
                )
            else:
                ax.quiver(
                    p[0] - v[0], p[1] - v[1], p[2] - v[2], v[0], v[1], v[2], color="tab:purple"
                )
    if planar:
        ax.set_xlabel("x [m]")
        ax.set_ylabel("z [m]")
        ax.set_aspect("equal", adjustable="datalim")
    else:
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        _equal_3d(ax, P, L)
    return ax


def _equal_3d(ax, P, L):
    c = 0.5 * (P.max(axis=0) + P.min(axis=0))
    h = 0.55 * max(float(np.ptp(P, axis=0).max()), 0.2 * L)
    ax.set_xlim(c[0] - h, c[0] + h)
    ax.set_ylim(c[1] - h, c[1] + h)
    ax.set_zlim(c[2] - h, c[2] + h)


def shapes(
    curves: dict,
    ax=None,
    plane: str = "xz",
    styles: dict | None = None,
    scale: float = 1.0,
    unit: str = "m",
):
    """Backbones ``{label: (N, 3) positions [m]}`` projected on ``plane`` ('xz', 'yz'
    or 'xy'); ``scale`` multiplies coordinates (1e3 with unit='mm')."""
    ax = _ax(ax)
    i, j = ("xyz".index(plane[0]), "xyz".index(plane[1]))
    for label, P in curves.items():
        P = np.asarray(P) * scale
        ax.plot(P[:, i], P[:, j], label=label, **(styles or {}).get(label, {}))
    ax.set_xlabel(f"{plane[0]} [{unit}]")
    ax.set_ylabel(f"{plane[1]} [{unit}]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize="small")
    return ax


def sweep_lines(res, x: str, y: str, component=None, ax=None, xlabel=None, ylabel=None, **kwargs):
    """Plot a recorded quantity of a :class:`tendonrod.SweepResult` against one varied
    parameter: one line per combination of the other grid axes (labelled with their
    values); points that did not converge are left out (NaN).

    ``x``: a varied name (its values must be scalars, or vectors, which are plotted by
    their norm); ``y``: a recorded key; ``component``: index into the item shape (e.g.
    ``0`` for the x of ``tip_position``, ``(2, 2)`` for a rotation entry).  Give
    ``xlabel``/``ylabel`` with units; the defaults are the names.
    """
    ax = _ax(ax)
    names = list(res.names)
    if x not in names:
        raise ValueError(f"x={x!r} is not a varied parameter ({', '.join(names)})")
    shape = tuple(res.shape)
    nd = len(shape)
    ys = np.asarray(res[y], dtype=float)
    if component is not None:
        comp = component if isinstance(component, tuple) else (component,)
        ys = ys[(slice(None),) * nd + comp]
    if ys.shape != shape:
        raise ValueError(f"{y!r} has item shape {ys.shape[nd:]}; choose a component")
    ys = np.where(res.success, ys, np.nan)
    xv = np.asarray(res[x], dtype=float)
    if xv.ndim > nd:
        xv = np.linalg.norm(xv.reshape(shape + (-1,)), axis=-1)
        xlabel = xlabel or f"|{x}|"
    axis = names.index(x) if nd == len(names) else 0
    others = [k for k in range(nd) if k != axis]
    for combo in np.ndindex(*[shape[k] for k in others]):
        idx = [0] * nd
        for k, c in zip(others, combo):
            idx[k] = c
        sl = list(idx)
        sl[axis] = slice(None)
        lab = ", ".join(
            f"{names[k]} = {_fmt(np.asarray(res[names[k]])[tuple(idx)])}" for k in others
        )
        ax.plot(xv[tuple(sl)], ys[tuple(sl)], label=lab or None, **kwargs)
    if others:
        ax.legend(fontsize="x-small")
    ax.set_xlabel(xlabel or x)
    ax.set_ylabel(ylabel or (y if component is None else f"{y}[{component}]"))
    ax.grid(alpha=0.3)
    return ax


def _fmt(v):
    v = np.asarray(v)
    if v.ndim:
        return "(" + ", ".join(_fmt(e) for e in v.ravel()) + ")"
    try:
        return f"{float(v):.4g}"
    except (TypeError, ValueError):
        return str(v)


def sigma_vs_zeta(data: dict, ax=None, slope_labels: bool = True):
    """Figs. 3 / 6: sigma at the loaded point against zeta = z/L (closed forms);
    ``data`` from :func:`tendonrod.studies.closed_form_sigma_vs_zeta`."""
    ax = _ax(ax)
    z = data["zeta"]
    import matplotlib as mpl

    ax.plot(z, data["no tendon"], "r-", label=r"no tendon ($4\zeta^3$)")
    slopes = [k for k in data if not isinstance(k, str)]
    cmap = mpl.colormaps["winter"]
    for a in slopes:
        lab = (
            (
                "parallel, inextensible"
                if a == 0
                else "converging ($a=-b/L$)"
                if a == -1
                else f"$aL/b = {a:g}$"
            )
            if slope_labels
            else None
        )
        ax.plot(z, data[a], color="b" if len(slopes) == 1 else cmap(min(-a, 1.0)), label=lab)
    ax.set_xlabel(ZETA_LABEL)
    ax.set_ylabel(SIGMA_LABEL + " at the loaded point")
    ax.set_xlim(0, 1)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def tip_sigma_vs_alpha(data: dict, ax=None, style: str = "-", label_suffix: str = ""):
    """Fig. 7: tip sigma against alpha = r^2 k L / EI (closed forms, log x);
    ``data`` from :func:`tendonrod.studies.closed_form_tip_sigma_vs_alpha`."""
    ax = _ax(ax)
    ax.semilogx(data["alpha"], data["parallel"], "b" + style, label="parallel" + label_suffix)
    ax.semilogx(data["alpha"], data["converging"], "g" + style, label="converging" + label_suffix)
    ax.set_xlabel(ALPHA_LABEL + r"  (converging: $b^2 k L / EI$)")
    ax.set_ylabel("tip " + SIGMA_LABEL)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="small")
    return ax


_DIR_STYLE = {"transverse": "-", "axial": "--", "out-of-plane": ":"}
_ROUTE_COLOR = {"parallel": "tab:blue", "converging": "tab:green"}


def compliance_map(data: dict, direction: str, ax=None):
    """Figs. 13-15: sigma(zeta) in one load ``direction`` ('transverse', 'axial',
    'out-of-plane') for the actuated robot; ``data`` from
    :func:`tendonrod.studies.compliance_map`."""
    ax = _ax(ax)
    z = data["zeta"]
    for key, y in data.items():
        if not (isinstance(key, tuple) and len(key) == 3 and key[2] == direction):
            continue
        routing, held, _ = key
        ax.plot(
            z,
            y,
            color=_ROUTE_COLOR.get(routing),
            ls="-" if held == "displacement held" else "--",
            marker="o" if held == "displacement held" else None,
            ms=3,
            label=f"{routing}, {held}",
        )
    ax.set_xlabel(ZETA_LABEL)
    ax.set_ylabel(SIGMA_LABEL + f" ({direction})")
    ax.set_xlim(0, 1)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def tip_compliance_vs_alpha(data: dict, ax=None, closed: bool = True):
    """Fig. 16: tip sigma against alpha for the actuated robot, parallel and converging,
    three directions; dotted black: the straight-robot closed forms of Fig. 7.
    ``data`` from :func:`tendonrod.studies.tip_compliance_vs_alpha`."""
    ax = _ax(ax)
    a = data["alpha"]
    for routing in ("parallel", "converging"):
        for d, ls in _DIR_STYLE.items():
            if (routing, d) in data:
                ax.loglog(
                    a,
                    data[(routing, d)],
                    color=_ROUTE_COLOR[routing],
                    ls=ls,
                    marker=".",
                    label=f"{routing}, {d}",
                )
    if closed and "closed" in data:
        c = data["closed"]
        ax.loglog(c["alpha"], c["parallel"], "k:", lw=1, label="closed form, straight (Fig. 7)")
        ax.loglog(c["alpha"], c["converging"], "k:", lw=1)
    ax.set_xlabel(ALPHA_LABEL + r"  (converging: $b^2 k L / EI$)")
    ax.set_ylabel("tip " + SIGMA_LABEL)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize="x-small", ncol=2)
    return ax


def tension_vs_load(F, tension, ax=None, labels=None, ylabel: str = "tendon tension [N]"):
    """Fig. 17: tendon tension(s) (K, nt) [N] against load F (K,) [N]."""
    ax = _ax(ax)
    T = np.asarray(tension).reshape(len(F), -1)
    for i in range(T.shape[1]):
        lab = labels[i] if labels else f"tendon {i}"
        ax.plot(F, T[:, i], marker=".", label=lab)
    ax.set_xlabel("tip load F [N]")
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def torsion(data: dict, ax=None):
    """Fig. 12: tip twist against the nondimensional twisting moment M L / GJ for growing
    tendon stiffness; ``data`` from :func:`tendonrod.studies.torsion_paradox`."""
    ax = _ax(ax)
    M = data["M_nd"]
    ax.plot(np.degrees(data["no tendon"]), M, "k--", label="rod alone")
    for a in data["alphas"]:
        ax.plot(np.degrees(data[a]), M, marker=".", label=f"{ALPHA_LABEL} = {a:g}")
    ax.set_xlabel(r"tip twist $\phi$ [deg]")
    ax.set_ylabel(r"twisting moment $M L / GJ$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def straight_load(data: dict, ax=None):
    """Fig. 10: tip deflection delta/L against F L^2/EI, Cosserat (markers) and closed
    forms (lines); ``data`` from :func:`tendonrod.studies.straight_load_sweep`."""
    ax = _ax(ax)
    F = data["F_nd"]
    colors = {"no tendon": "tab:red", "parallel": "tab:blue", "converging": "tab:green"}
    for name, c in colors.items():
        if name not in data:
            continue
        d = data[name]
        ax.plot(F, d["closed"], color=c, ls="--", label=f"{name}, closed form")
        cos = np.where(d["success"], d["cosserat"], np.nan)
        ax.plot(F[-len(cos) :], cos, color=c, marker="o", ms=3, ls="-", label=f"{name}, Cosserat")
    ax.set_xlabel(r"tip load $F L^2 / EI$")
    ax.set_ylabel(r"tip deflection $\delta / L$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="x-small")
    return ax


def prototype_deflection(data: dict, ax=None):
    """Figs. 20-21: deflection at the loaded point [mm] against load location z [mm] with
    the calibrated EI and k; ``data`` from :func:`tendonrod.studies.prototype_curves`.
    Markers at the 8 load locations are model values (the measured points are not
    public)."""
    ax = _ax(ax)
    z, zl = 1e3 * data["z"], 1e3 * data["z_loads"]
    masses = sorted({k[1] for k in data if isinstance(k, tuple)})
    m0 = masses[0]
    ax.plot(z, 1e3 * data[("delta_free", m0)], "r--", label=f"no tendon, {1e3 * m0:.0f} g (EI fit)")
    for m, c in zip(masses, ("tab:blue", "tab:purple")):
        ax.plot(z, 1e3 * data[("delta", m)], color=c, label=f"tendon, {1e3 * m:.0f} g")
        ax.plot(zl, 1e3 * data[("delta_loads", m)], "o", color=c, mfc="none", ms=5)
    ax.set_xlabel("load location z [mm]")
    ax.set_ylabel(r"deflection at the load $\delta(z)$ [mm]")
    ax.set_title(
        f"{data['routing']}: EI = {data['EI'] * 1e6:.3g} N mm$^2$, k = {data['k'] * 1e-3:.3g} N/mm, "
        f"$r^2kL/EI$ = {data['alpha']:.2f}",
        fontsize="small",
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def prototype_tension(datas, ax=None):
    """Fig. 22: tendon tension [N] against load location z [mm] for each member and
    weight (eqs. 6 and 25, calibrated EI and k)."""
    ax = _ax(ax)
    for data, c in zip(datas, ("tab:blue", "tab:green")):
        masses = sorted({k[1] for k in data if isinstance(k, tuple)})
        for m, ls in zip(masses, ("--", "-")):
            ax.plot(
                1e3 * data["z"],
                data[("tension", m)],
                color=c,
                ls=ls,
                label=f"{data['routing']}, {1e3 * m:.0f} g",
            )
            ax.plot(
                1e3 * data["z_loads"], data[("tension_loads", m)], "o", color=c, mfc="none", ms=4
            )
    ax.set_xlabel("load location z [mm]")
    ax.set_ylabel(r"tendon tension $\tau$ [N]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def prototype_shapes(data: dict, ax=None):
    """Fig. 23: loaded shapes (closed-form tangent angle integrated) for the last four
    load locations, 0.2 N (solid) and 0.5 N (dashed); y positive downwards along the
    load.  ``data`` from :func:`tendonrod.studies.prototype_shapes`."""
    ax = _ax(ax)
    colors = ["tab:blue", "tab:orange", "tab:green", "tab:red"]
    for F, ls, mk in zip(data["forces"], ("-", "--"), ("o", "s")):
        for z, c in zip(data["z"], colors):
            xy = 1e3 * np.asarray(data[(F, z)])
            ax.plot(xy[:, 0], -xy[:, 1], color=c, ls=ls, label=f"F = {F:g} N, z = {1e3 * z:.0f} mm")
            pt = 1e3 * np.asarray(data[("point", F, z)])
            ax.plot(pt[0], -pt[1], mk, color=c, mfc="none" if ls == "--" else c, ms=4)
    ax.set_xlabel("x along the unloaded member [mm]")
    ax.set_ylabel("y [mm] (load downwards)")
    ax.set_title(data["routing"], fontsize="small")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="x-small", ncol=2)
    return ax


# --------------------------------------------------------------------------- the paper's figures
def _figure(w=6.4, h=4.8):
    from matplotlib.figure import Figure

    return Figure(figsize=(w, h), layout="constrained")


def paper_figures():
    """[(key, caption, make(fast) -> matplotlib Figure), ...] for the ``figures`` command."""
    from . import studies as S

    def fig01(fast=False):
        d = S.prescribed_comparison(theta=0.0, force=(-0.5, 0.0, 0.0))
        fig = _figure()
        ax = fig.add_subplot()
        shapes(
            {
                "unloaded": d["unloaded"],
                "tension held (tau = 0)": d["tension held"],
                "displacement held (q = 0)": d["displacement held"],
            },
            ax=ax,
            styles={"unloaded": {"color": "0.6", "ls": ":"}},
        )
        ax.set_title(
            "0.5 N tip load, Sec. IV-B robot, one inextensible parallel tendon", fontsize="small"
        )
        tip_t = -d["tension held"][-1, 0]
        tip_d = -d["displacement held"][-1, 0]
        fig._tendonrod_notes = (
            f"Tip deflection: tension held {1e3 * tip_t:.2f} mm (closed form FL^3/3EI "
            f"{1e3 * d['closed tension held']:.2f} mm), displacement held "
            f"{1e3 * tip_d:.2f} mm (closed form FL^3/12EI "
            f"{1e3 * d['closed displacement held']:.2f} mm); tendon tension "
            f"{d['displacement held tension']:.2f} N."
        )
        return fig

    def fig03(fast=False):
        fig = _figure()
        sigma_vs_zeta(S.closed_form_sigma_vs_zeta(slopes=(0.0,)), ax=fig.add_subplot())
        return fig

    def fig06(fast=False):
        fig = _figure()
        sigma_vs_zeta(
            S.closed_form_sigma_vs_zeta(slopes=(0.0, -0.25, -0.5, -0.75, -1.0)),
            ax=fig.add_subplot(),
        )
        return fig

    def fig07(fast=False):
        fig = _figure()
        tip_sigma_vs_alpha(S.closed_form_tip_sigma_vs_alpha(), ax=fig.add_subplot())
        return fig

    def fig08(fast=False):
        d = S.actuation_tradeoff()
        fig = _figure(10, 4.8)
        a1, a2 = fig.subplots(1, 2)
        shapes(
            {
                f"parallel: tau = {d['parallel']['tension']:.1f} N, q = {100 * d['parallel']['q_over_L']:.1f}% L": d[
                    "parallel"
                ]["shape"],
                f"converging: tau = {d['converging']['tension']:.1f} N, q = {100 * d['converging']['q_over_L']:.1f}% L": d[
                    "converging"
                ]["shape"],
            },
            ax=a1,
            scale=1e3,
            unit="mm",
        )
        a1.set_title("actuated to 90 deg, no load", fontsize="small")
        cur = {
            f"{r}, q = {1e3 * d[r]['q_loaded']:.1f} mm": d[r]["shape_loaded"]
            for r in ("parallel", "converging")
            if d[r]["shape_loaded"] is not None
        }
        if cur:
            shapes(cur, ax=a2, scale=1e3, unit="mm")
        a2.set_title(f"{d['load']} N tip load, actuated back to the base axis", fontsize="small")
        fig._tendonrod_notes = "; ".join(
            f"{r}: tension {d[r]['tension']:.2f} N (closed form eqs. 37-38: {d[r]['tension_closed_form']:.2f} N), "
            f"displacement {100 * d[r]['q_over_L']:.2f}% of L"
            for r in ("parallel", "converging")
        )
        return fig

    def fig10(fast=False):
        d = S.straight_load_sweep(loads=np.linspace(0.0, 3.0, 11 if fast else 31))
        fig = _figure()
        straight_load(d, ax=fig.add_subplot())
        c = d["converging"]
        fig._tendonrod_notes = (
            f"At F L^2/EI = {d['F_nd'][-1]:g}: Cosserat tip deflection / L = "
            + ", ".join(
                f"{k} {d[k]['cosserat'][-1]:.4g} (closed form {d[k]['closed'][-1]:.4g})"
                for k in ("no tendon", "parallel", "converging")
            )
            + f"; with the inextensible converging tendon the tip stays put even at "
            f"large loads (largest |deflection| {np.nanmax(np.abs(c['cosserat'])):.1e} L)."
        )
        return fig

    def fig11(fast=False):
        fig = _figure(13, 4.6)
        a1 = fig.add_subplot(1, 3, 1)
        a2 = fig.add_subplot(1, 3, 2)
        a3 = fig.add_subplot(1, 3, 3)
        notes = []
        for ax, f, name in (
            (a1, (-0.5, 0.0, 0.0), "transverse"),
            (a2, (0.0, 0.0, -0.5), "vertical"),
        ):
            d = S.prescribed_comparison(theta=math.pi / 2, force=f)
            shapes(
                {
                    "unloaded": d["unloaded"],
                    "tension held": d["tension held"],
                    "displacement held": d["displacement held"],
                },
                ax=ax,
                styles={"unloaded": {"color": "0.6", "ls": ":"}},
            )
            ax.set_title(f"({'ab'[name == 'vertical']}) {name} 0.5 N tip load", fontsize="small")
            notes.append(
                f"{name}: tension with displacement held {d['displacement held tension']:.2f} N"
            )
        d = S.out_of_plane_comparison()
        cur = {"unloaded": d["unloaded"], "tension held": d["tension held"]}
        for key, P_ in d.items():
            if isinstance(key, tuple) and key[0] == "displacement held":
                cur[f"displacement held, $r^2kL/3EI$ = {key[1]:g}"] = P_
                notes.append(
                    f"out-of-plane, r^2kL/3EI = {key[1]:g}: tip y = {1e3 * P_[-1, 1]:.2f} mm"
                )
        notes.append(f"out-of-plane, tension held: tip y = {1e3 * d['tension held'][-1, 1]:.2f} mm")
        shapes(
            cur,
            ax=a3,
            plane="xy",
            scale=1e3,
            unit="mm",
            styles={"unloaded": {"color": "0.6", "ls": ":"}},
        )
        a3.set_aspect("auto")
        a3.set_title("(c) three tendons, out-of-plane 0.5 N (top view)", fontsize="small")
        fig._tendonrod_notes = "; ".join(notes)
        return fig

    def fig12(fast=False):
        d = S.torsion_paradox(n=9 if fast else 21)
        fig = _figure()
        torsion(d, ax=fig.add_subplot())
        fig._tendonrod_notes = (
            "Twist at M L/GJ = 0.5: "
            + ", ".join(f"alpha = {a:g}: {np.degrees(d[a][-1]):.2f} deg" for a in d["alphas"])
            + f" (rod alone {np.degrees(d['M_nd'][-1]):.2f} deg)."
        )
        return fig

    def make_map(direction):
        cache = {}

        def f(fast=False):
            if fast not in cache:
                zeta = np.linspace(0.1, 1.0, 5 if fast else 19)
                cache[fast] = S.compliance_map(zeta=zeta)
            fig = _figure()
            d = cache[fast]
            compliance_map(d, direction, ax=fig.add_subplot())
            fig.axes[0].set_title(
                f"actuated to 90 deg, {ALPHA_LABEL} = {S.ALPHA_PAPER:.3g}", fontsize="small"
            )
            fig._tendonrod_notes = (
                "Tip sigma: "
                + "; ".join(
                    f"{k[0]}, {k[1]}: {v[-1]:.4g}"
                    for k, v in d.items()
                    if isinstance(k, tuple) and len(k) == 3 and k[2] == direction
                )
                + "."
            )
            return fig

        return f

    def fig16(fast=False):
        d = S.tip_compliance_vs_alpha(alphas=np.logspace(-1, 4, 6 if fast else 21))
        fig = _figure()
        tip_compliance_vs_alpha(d, ax=fig.add_subplot())
        fig.axes[0].set_title("tip compliance, actuated to 90 deg", fontsize="small")
        notes = []
        for dname in S.DIRECTIONS:
            better = d[("converging", dname)] < d[("parallel", dname)]
            notes.append(
                f"{dname}: converging stiffer "
                + (
                    "at every alpha on the grid"
                    if better.all()
                    else f"from alpha = {d['alpha'][np.argmax(better)]:.3g} on the grid"
                    if better.any()
                    else "nowhere"
                )
            )
        fig._tendonrod_notes = (
            "; ".join(notes) + " (the paper: transverse always, axial above about 15)."
        )
        return fig

    def make_slack(opposing):
        def f(fast=False):
            d = S.slack_study(opposing=opposing, n=11 if fast else 41)
            fig = _figure(10, 4.4)
            a1, a2 = fig.subplots(1, 2)
            labels = ["tendon at +x", "tendon at -x"]
            tension_vs_load(
                d["F"],
                d["locked"]["tension"],
                ax=a1,
                labels=labels[: d["locked"]["tension"].shape[1]],
            )
            a1.set_title("displacement held", fontsize="small")
            for key, ls in (("locked", "-"), ("held", "--")):
                td = d[key]["tip_displacement"]
                a2.plot(
                    d["F"],
                    1e3 * np.linalg.norm(td, axis=1),
                    ls=ls,
                    marker=".",
                    label=f"|tip displacement|, {'displacement' if key == 'locked' else 'tension'} held",
                )
            ax3 = a2.twinx()
            ax3.plot(
                d["F"],
                np.degrees(d["locked"]["tip_angle"]),
                "k:",
                label="tip angle (displacement held)",
            )
            ax3.set_ylabel("tip angle [deg]")
            lo, hi = ax3.get_ylim()
            if hi - lo < 10.0:  # a held angle: do not magnify round-off
                mid = 0.5 * (hi + lo)
                ax3.set_ylim(mid - 5.0, mid + 5.0)
            a2.set_xlabel("tip load F [N] (vertical, downwards)")
            a2.set_ylabel("tip displacement [mm]")
            a2.legend(fontsize="x-small", loc="upper left")
            ax3.legend(fontsize="x-small", loc="lower right")
            fig._tendonrod_notes = (
                f"Load at which the first tendon goes slack: {d['F_slack']:.3g} N."
                if math.isfinite(d["F_slack"])
                else "No tendon went slack in the load range."
            )
            return fig

        return f

    def make_proto(routing):
        def f(fast=False):
            fig = _figure()
            prototype_deflection(S.prototype_curves(routing), ax=fig.add_subplot())
            return fig

        return f

    def fig22(fast=False):
        fig = _figure()
        prototype_tension(
            [S.prototype_curves("parallel"), S.prototype_curves("converging")], ax=fig.add_subplot()
        )
        return fig

    def fig23(fast=False):
        fig = _figure(11, 4.4)
        a1, a2 = fig.subplots(1, 2, sharey=True)
        prototype_shapes(S.prototype_shapes("parallel"), ax=a1)
        prototype_shapes(S.prototype_shapes("converging"), ax=a2)
        return fig

    return [
        (
            "fig01",
            "Fig. 1: prescribed displacement vs prescribed tension. Straight robot of Sec. IV-B "
            "(Kirchhoff, L = 0.1 m, d = 1.04 mm, one inextensible parallel tendon at 10 mm), 0.5 N "
            "transverse tip load: with the tension held (here 0) the robot deflects as a plain "
            "cantilever, with the tendon displacement held it deflects about a quarter as much "
            "(eq. 12). Cosserat model.",
            fig01,
        ),
        (
            "fig03",
            "Fig. 3: nondimensional compliance at the loaded point against load location, "
            "no tendon (eq. 10 with k = 0) and one inextensible parallel tendon (eq. 11). Closed form.",
            fig03,
        ),
        (
            "fig06",
            "Fig. 6: the same for sloped inextensible tendons, a L / b from 0 (parallel) to -1 "
            "(converging, zero tip compliance, eqs. 29, 33). Closed form.",
            fig06,
        ),
        (
            "fig07",
            "Fig. 7: tip compliance against nondimensional tendon stiffness for parallel (eq. 9) "
            "and converging (eq. 32) routing. Closed form.",
            fig07,
        ),
        (
            "fig08",
            "Fig. 8: actuation trade-off on the Sec. V prototypes (calibrated EI, k): shapes at a "
            "90 deg tip angle (constant vs linearly varying curvature) with the tension and tendon "
            "displacement needed, and the shapes under a 0.9 N tip load actuated back until the tip "
            "is on the base axis. Cosserat model.",
            fig08,
        ),
        (
            "fig10",
            "Fig. 10: closed forms against the Cosserat model for the initially straight robot "
            "(Sec. IV-B) under a growing transverse tip load, tendon locked at q = 0.",
            fig10,
        ),
        (
            "fig11",
            "Fig. 11: robot of Sec. IV-B actuated to 90 deg, prescribed displacement vs prescribed "
            "tension: (a) transverse and (b) vertical in-plane 0.5 N tip loads, one inextensible "
            "tendon; (c) three stretchable tendons, out-of-plane 0.5 N tip load, r^2kL/3EI = 50 and "
            "5e4. Cosserat model.",
            fig11,
        ),
        (
            "fig12",
            "Fig. 12: torsion paradox. Straight robot of Sec. IV-B, three parallel tendons locked "
            "at q = 0, pure twisting moment at the tip; the curve stiffens with tendon stiffness but "
            "its slope at zero stays GJ/L. Cosserat model.",
            fig12,
        ),
        (
            "fig13",
            "Fig. 13: compliance at a loaded point for transverse (horizontal, in-plane) loads, "
            "robot of Sec. IV-B actuated to 90 deg, one tendon, r^2kL/EI = 8.29e6; displacement "
            "held (solid) and tension held (dashed). Cosserat model, linearised (small loads).",
            make_map("transverse"),
        ),
        ("fig14", "Fig. 14: the same for axial (vertical, in-plane) loads.", make_map("axial")),
        ("fig15", "Fig. 15: the same for out-of-plane loads.", make_map("out-of-plane")),
        (
            "fig16",
            "Fig. 16: tip compliance against nondimensional tendon stiffness, actuated to 90 deg, "
            "parallel and converging, three load directions (Cosserat, locked actuator), with the "
            "straight-robot closed forms of Fig. 7 dotted.",
            fig16,
        ),
        (
            "fig17",
            "Fig. 17: robot of Figs. 17-18 (L = 0.2 m, d = 0.8 mm) with one inextensible tendon, "
            "actuated to 90 deg and locked, under a growing downward tip load: the tension falls to "
            "zero, the tendon goes slack, and the tip then rotates. Cosserat model.",
            make_slack(False),
        ),
        (
            "fig18",
            "Fig. 18: the same with an opposing tendon; both pretensioned (5 N before locking; "
            "r^2kL/EI = 1e5: an opposing pair needs some stretch for a defined tension level) so "
            "neither goes slack and the tip keeps its orientation.",
            make_slack(True),
        ),
        (
            "fig20",
            "Fig. 20: parallel prototype, deflection at the loaded point against load location "
            "(eq. 8 with the calibrated EI = 11.2e3 N mm^2, k = 4.5 N/mm, L = 201 mm, r = 8 mm). "
            "Formulas only: the measured points are not available.",
            make_proto("parallel"),
        ),
        (
            "fig21",
            "Fig. 21: converging prototype (offset 8 -> 1.875 mm), eq. 27 with EI = 11.3e3 N mm^2, "
            "k = 8.55 N/mm. Formulas only.",
            make_proto("converging"),
        ),
        (
            "fig22",
            "Fig. 22: tendon tension against load location for 20 g and 50 g weights, both "
            "prototypes (eqs. 6 and 25). Formulas only.",
            fig22,
        ),
        (
            "fig23",
            "Fig. 23: loaded shapes of both prototypes for the last four load locations at 0.2 N "
            "and 0.5 N (closed-form tangent angle integrated). Formulas only.",
            fig23,
        ),
    ]
