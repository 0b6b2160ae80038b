"""The paper's studies and figures: the data behind each figure, computed by the library.

One function per study returns plain arrays (a dict); :mod:`tendonrod.paper.charts`
(and the generic :mod:`tendonrod.plot`) draw them, and
:func:`~tendonrod.paper.figures.figure_registry` pairs the two for
``python -m tendonrod figures``.  Notebooks call the same functions.  The physics
lives in :mod:`tendonrod.analytic` (closed forms) and :func:`tendonrod.solve` /
:func:`tendonrod.compliance` (Cosserat model); here are only the paper's parameter
sets, the actuation to a target tip angle, and the loops.

- :mod:`~tendonrod.paper.robots` -- parameter sets, rods, one-tendon robots, :func:`actuate`
- :mod:`~tendonrod.paper.closed_forms` -- Figs. 3, 6, 7 and the design question
- :mod:`~tendonrod.paper.prototype` -- the Section V prototypes (Figs. 8, 20-23)
- :mod:`~tendonrod.paper.studies` -- the Cosserat-model studies (Figs. 1, 10-18)
- :mod:`~tendonrod.paper.friction` -- channel friction on the prototype (Fig. 25, hysteresis)
- :mod:`~tendonrod.paper.charts`, :mod:`~tendonrod.paper.figures` -- drawing them

Every study function is importable from here (``tendonrod.paper.actuate``, ...).

Conventions used throughout
---------------------------
- Nondimensional compliance (the paper's): sigma = 12 EI delta / (F L^3),
  with delta the displacement of the loaded point in the direction of the
  force F.  From the Cosserat model, delta/F is the diagonal entry
  d^T C d of the translational block of :func:`tendonrod.compliance` for the
  unit direction d (a linearisation: "small loads", as the paper's charts).
- Nondimensional tendon stiffness alpha = r^2 k L / EI with r the base offset
  and k = EA / L the tendon's spring constant (so EA = alpha EI / r^2).
  For a converging tendon the real spring constant is EA/(c L) with
  c = sqrt(1 + a^2) -- c - 1 < 1e-2 for every design here.
- Geometry of the actuated robot (Figs. 11, 13-18): the base is clamped with
  the rod along +z (vertical), the tendon at +x pulls the tip over towards +x,
  so "actuated to 90 degrees" means the tip tangent points along +x.  The
  paper's load directions are then: *transverse* = world x (horizontal, in the
  bending plane), *axial* = world z (vertical, in the bending plane),
  *out-of-plane* = world y.
- Closed-form sign convention (as :mod:`tendonrod.analytic`): F > 0 points
  away from the tendon side; delta > 0 along F.
"""

from .closed_forms import closed_form_sigma_vs_zeta, closed_form_tip_sigma_vs_alpha, design_study
from .figures import FigureEntry, fast_mode, figure_registry
from .friction import (
    actuation_hysteresis,
    axial_load_band,
    axial_load_study,
    friction_robot,
    loading_slip,
)
from .prototype import (
    PROTOTYPE,
    Prototype,
    actuation_tradeoff,
    prototype_curves,
    prototype_shapes,
)
from .robots import (
    ALPHA_PAPER,
    DIRECTIONS,
    G_ACCEL,
    Actuation,
    actuate,
    paper_rod_ivb,
    paper_rod_slack,
    sigma_from_compliance,
    single_tendon_robot,
    tendon_EA,
    tip_angle,
)
from .studies import (
    compliance_map,
    critical_slack_load,
    out_of_plane_comparison,
    prescribed_comparison,
    slack_study,
    straight_load_sweep,
    tip_compliance_vs_alpha,
    torsion_paradox,
)

__all__ = [
    "G_ACCEL",
    "ALPHA_PAPER",
    "DIRECTIONS",
    "PROTOTYPE",
    "Prototype",
    "paper_rod_ivb",
    "paper_rod_slack",
    "tendon_EA",
    "single_tendon_robot",
    "tip_angle",
    "Actuation",
    "actuate",
    "sigma_from_compliance",
    "closed_form_sigma_vs_zeta",
    "closed_form_tip_sigma_vs_alpha",
    "prototype_curves",
    "prototype_shapes",
    "actuation_tradeoff",
    "straight_load_sweep",
    "prescribed_comparison",
    "out_of_plane_comparison",
    "torsion_paradox",
    "compliance_map",
    "tip_compliance_vs_alpha",
    "slack_study",
    "critical_slack_load",
    "design_study",
    "friction_robot",
    "axial_load_band",
    "axial_load_study",
    "actuation_hysteresis",
    "loading_slip",
    "FigureEntry",
    "figure_registry",
    "fast_mode",
]
