"""The paper's charts (matplotlib, imported inside each function), drawn from the data
of :mod:`tendonrod.paper`'s studies.  As in :mod:`tendonrod.plot`, every function takes
``ax=None`` (None: the current Axes of pyplot), labels the axes with units or as the
nondimensional group, returns the Axes, and never calls ``plt.show()`` or ``savefig``.

:func:`sigma_vs_zeta` (Figs. 3, 6), :func:`tip_sigma_vs_alpha` (Fig. 7),
:func:`compliance_map` (Figs. 13-15), :func:`tip_compliance_vs_alpha` (Fig. 16),
:func:`torsion` (Fig. 12), :func:`straight_load` (Fig. 10),
:func:`prototype_deflection`, :func:`prototype_tension`, :func:`prototype_shapes`
(Figs. 20-23), :func:`friction_band` (Fig. 25 with friction),
:func:`friction_hysteresis` (actuation hysteresis).  Tensions against load (Figs. 17-18) are the generic
:func:`tendonrod.plot.tension_vs_load`.
"""

from __future__ import annotations

import math

import numpy as np

from ..plot import _ax

__all__ = [
    "sigma_vs_zeta",
    "tip_sigma_vs_alpha",
    "compliance_map",
    "tip_compliance_vs_alpha",
    "torsion",
    "straight_load",
    "prototype_deflection",
    "prototype_tension",
    "prototype_shapes",
    "friction_band",
    "friction_hysteresis",
]

SIGMA_LABEL = r"$\sigma = 12\,EI\,\delta\,/\,(F L^3)$"
ZETA_LABEL = r"$\zeta = z / L$"
ALPHA_LABEL = r"$r^2 k L\,/\,EI$"
TITLE_SIZE = "medium"  # titles at the tick labels' size (matplotlib's default ticks: medium)


def sci(x: float, digits: int = 3) -> str:
    """``x`` for a label: plain when 1e-3 <= |x| < 1e4, else mathtext ``a \\times 10^{n}``
    (never Python's ``8.29e+06``)."""
    if x == 0 or not math.isfinite(x) or 1e-3 <= abs(x) < 1e4:
        return f"{x:.{digits}g}"
    n = math.floor(math.log10(abs(x)))
    m = x / 10**n
    if float(f"{m:.{digits}g}") == 10:
        m, n = m / 10, n + 1
    return rf"${m:.{digits}g} \times 10^{{{n}}}$"


def sigma_vs_zeta(data: dict, ax=None, slope_labels: bool = True):
    """Figs. 3 / 6: sigma at the loaded point against zeta = z/L (closed forms);
    ``data`` from :func:`tendonrod.paper.closed_form_sigma_vs_zeta`."""
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
    ``data`` from :func:`tendonrod.paper.closed_form_tip_sigma_vs_alpha`."""
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
    :func:`tendonrod.paper.compliance_map`."""
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
    ``data`` from :func:`tendonrod.paper.tip_compliance_vs_alpha`."""
    ax = _ax(ax)
    a = data["alpha"]
    # six curves, some of which coincide (where the routing does not matter): a marker per
    # direction, filled and small for parallel, hollow and larger for converging, so that
    # a curve lying on another still shows
    markers = {"transverse": "o", "axial": "s", "out-of-plane": "^"}
    for routing in ("parallel", "converging"):
        hollow = routing == "converging"
        for d, ls in _DIR_STYLE.items():
            if (routing, d) in data:
                ax.loglog(
                    a,
                    data[(routing, d)],
                    color=_ROUTE_COLOR[routing],
                    ls=ls,
                    marker=markers[d],
                    ms=7 if hollow else 3.5,
                    mfc="none" if hollow else _ROUTE_COLOR[routing],
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


def torsion(data: dict, ax=None):
    """Fig. 12: tip twist against the nondimensional twisting moment M L / GJ for growing
    tendon stiffness; ``data`` from :func:`tendonrod.paper.torsion_paradox`."""
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
    forms (lines); ``data`` from :func:`tendonrod.paper.straight_load_sweep`."""
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
    the calibrated EI and k; ``data`` from :func:`tendonrod.paper.prototype_curves`.
    Markers at the 8 load locations are model values (the measured points are not
    public)."""
    ax = _ax(ax)
    z, zl = 1e3 * data["z"], 1e3 * data["z_loads"]
    masses = sorted({k[1] for k in data if isinstance(k, tuple)})
    m0 = masses[0]
    ax.plot(z, 1e3 * data[("delta_free", m0)], "r--", label=f"no tendon, {1e3 * m0:.0f} g (EI fit)")
    for m, c in zip(masses, ("tab:blue", "tab:purple")):
        ax.plot(z, 1e3 * data[("delta", m)], color=c, label=f"tendon, {1e3 * m:.0f} g")
        # the model at the prototype's load locations: small filled dots on the curve (open
        # circles would read as measurements, which are not public)
        ax.plot(
            zl,
            1e3 * data[("delta_loads", m)],
            ".",
            color=c,
            ms=6,
            label="model at the load locations" if m == masses[-1] else None,
        )
    ax.set_xlabel("load location z [mm]")
    ax.set_ylabel(r"deflection at the load $\delta(z)$ [mm]")
    ax.set_title(
        f"{data['routing']}: EI = {data['EI'] * 1e6:.3g} N mm$^2$, k = {data['k'] * 1e-3:.3g} N/mm, "
        f"$r^2kL/EI$ = {data['alpha']:.2f}",
        fontsize=TITLE_SIZE,
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
            # the model at the load locations (small filled dots: no measurements)
            ax.plot(1e3 * data["z_loads"], data[("tension_loads", m)], ".", color=c, ms=5)
    ax.set_xlabel("load location z [mm]")
    ax.set_ylabel(r"tendon tension $\tau$ [N]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def prototype_shapes(data: dict, ax=None):
    """Fig. 23: loaded shapes (closed-form tangent angle integrated) for the last four
    load locations, 0.2 N (solid) and 0.5 N (dashed); y positive downwards along the
    load.  ``data`` from :func:`tendonrod.paper.prototype_shapes`."""
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
    ax.set_title(data["routing"], fontsize=TITLE_SIZE)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="x-small", ncol=2)
    return ax


def _friction_colors(frictions):
    import matplotlib as mpl

    cmap = mpl.colormaps["viridis"]
    n = max(len(frictions) - 1, 1)
    return {mu: cmap(0.85 * i / n) for i, mu in enumerate(frictions)}


def friction_band(data: dict, ax=None):
    """Fig. 25 with friction: tip deflection along the axial load [mm] against the load
    [N]; per mu the band between the tendon slid fully in (solid edge) and fully out
    (dashed edge), and the frictionless curve (black).  ``data`` from
    :func:`tendonrod.paper.axial_load_band`."""
    ax = _ax(ax)
    F = data["forces"]
    colors = _friction_colors(data["frictions"])
    for mu in data["frictions"]:
        lo, hi = 1e3 * data[mu]["out"]["deflection"], 1e3 * data[mu]["in"]["deflection"]
        c = colors[mu]
        ax.fill_between(F, lo, hi, color=c, alpha=0.2, lw=0)
        ax.plot(F, hi, color=c, ls="-", lw=1, label=rf"$\mu$ = {mu:g}: in (solid), out (dashed)")
        ax.plot(F, lo, color=c, ls="--", lw=1)
    # frictionless beneath, wide and grey: the sliding-in edges of small mu run along it
    ax.plot(
        F,
        1e3 * data[0.0]["none"]["deflection"],
        "-",
        color="0.6",
        lw=4,
        zorder=1.5,
        label="frictionless (grey, beneath)",
    )
    ax.set_xlabel("axial tip load F [N] (down the base axis)")
    ax.set_ylabel("tip deflection along the load [mm]")
    ax.set_title(
        f"actuated to {np.degrees(data['theta']):.0f} deg (sliding in), actuator locked",
        fontsize=TITLE_SIZE,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize="x-small", loc="upper left")
    return ax


def friction_hysteresis(data: dict, quantity: str = "theta", relative: bool = False, ax=None):
    """Actuation hysteresis against the tendon displacement q [mm]: the tip angle [deg]
    (``quantity="theta"``), the actuator tension [N] (``"tension"``) or the tip's x
    position [mm] (``"tip_x"``), pulling (sliding in, solid) and releasing (sliding out,
    dashed) for each mu, joined at the largest q (dotted: the tendon sticks while the
    actuator reverses), and the frictionless curve (black).  ``relative``: minus the
    frictionless value at the same q.  ``data`` from
    :func:`tendonrod.paper.actuation_hysteresis`."""
    ax = _ax(ax)
    q = 1e3 * data["q"]

    def value(branch):
        if quantity == "theta":
            return np.degrees(branch["theta"])
        if quantity == "tip_x":
            return 1e3 * branch["tip"][:, 0]
        return branch["tension"]

    base = value(data[0.0]["none"]) if relative else 0.0
    colors = _friction_colors(data["frictions"])
    for mu in data["frictions"]:
        c = colors[mu]
        yi, yo = value(data[mu]["in"]) - base, value(data[mu]["out"]) - base
        ax.plot(q, yi, color=c, ls="-", lw=1, label=rf"$\mu$ = {mu:g}: pulling / releasing")
        ax.plot(q, yo, color=c, ls="--", lw=1)
        ax.plot([q[-1], q[-1]], [yi[-1], yo[-1]], color=c, ls=":", lw=1)
    ax.plot(q, value(data[0.0]["none"]) - base, "k-", lw=1.5, label="frictionless")
    ax.set_xlabel("tendon displacement q [mm]")
    name = {"theta": "tip angle [deg]", "tip_x": "tip x [mm]", "tension": "actuator tension [N]"}
    ax.set_ylabel(name[quantity] + (" minus frictionless" if relative else ""))
    ax.grid(alpha=0.3)
    ax.legend(fontsize="x-small", loc="upper left" if not relative else "best")
    return ax
