"""Scene dataclasses and Options: section properties, validation messages, packing.

These run without the Cosserat core (no C solve is called)."""

import dataclasses
import math

import numpy as np
import pytest

import tendonrod as tr
from tendonrod.solver import pack_scene

ROD = dict(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9)


def test_round_section_properties():
    rod = tr.Rod(**ROD)
    d = 0.8e-3
    A, I = math.pi * d**2 / 4, math.pi * d**4 / 64
    # exact formulas evaluated the same way: agreement to a few ulps
    assert rod.bending_stiffness == pytest.approx(207e9 * I, rel=1e-15)
    assert rod.torsional_stiffness == pytest.approx(79.6e9 * 2 * I, rel=1e-15)
    assert rod.axial_stiffness == pytest.approx(207e9 * A, rel=1e-15)
    assert rod.shear_stiffness == pytest.approx(79.6e9 * A, rel=1e-15)


def test_overrides_and_kirchhoff():
    rod = tr.Rod(0.1, 1e-3, 200e9, 80e9, EI=1.5, GA=3e4)
    assert rod.bending_stiffness == 1.5
    assert rod.shear_stiffness == 3e4
    assert rod.axial_stiffness == pytest.approx(200e9 * math.pi * 1e-6 / 4, rel=1e-15)
    # a Cosserat rod's EA and GA are finite (the core solves v = e3 + K_se^-1 n_b);
    # rigidity in shear and extension is kirchhoff=True
    with pytest.raises(ValueError, match="GA"):
        tr.Rod(0.1, 1e-3, 200e9, 80e9, GA=np.inf)
    k = tr.Rod(length=0.1, EI=2.0, GJ=1.0, kirchhoff=True)
    assert k.axial_stiffness == math.inf and k.shear_stiffness == math.inf
    with pytest.raises(dataclasses.FrozenInstanceError):
        k.length = 3.0


@pytest.mark.parametrize(
    "kw, field, value",
    [
        (dict(length=0.0, diameter=1e-3, E=1e9, G=1e9), "length", "0.0"),
        (dict(length=-1.0, diameter=1e-3, E=1e9, G=1e9), "length", "-1.0"),
        (dict(length=math.nan, diameter=1e-3, E=1e9, G=1e9), "length", "nan"),
        (dict(length=math.inf, diameter=1e-3, E=1e9, G=1e9), "length", "inf"),
        (dict(length=0.1, diameter=-1e-3, E=1e9, G=1e9), "diameter", "-0.001"),
        (dict(length=0.1, diameter=1e-3, E=0.0, G=1e9), "E", "0.0"),
        (dict(length=0.1, diameter=1e-3, E=1e9, G=math.nan), "G", "nan"),
        (dict(length=0.1, diameter=1e-3, E=1e9, G=1e9, EI=math.inf), "EI", "inf"),
        (dict(length=0.1, diameter=1e-3, E=1e9, G=1e9, EA=-2.0), "EA", "-2.0"),
        (dict(length=0.1, EI=1.0, GJ=1.0), "EA", "None"),  # Cosserat rod needs EA, GA
        (dict(length=0.1, diameter=1e-3, E=1e9), "GJ", "None"),  # no G: no GJ
        (dict(length="long", EI=1.0, GJ=1.0, kirchhoff=True), "length", "long"),
    ],
)
def test_rod_validation_names_field_and_value(kw, field, value):
    with pytest.raises(ValueError) as e:
        tr.Rod(**kw)
    assert f"Rod.{field}" in str(e.value) and value in str(e.value)


@pytest.mark.parametrize(
    "kw, field, value",
    [
        (dict(offset=-0.01), "offset", "-0.01"),
        (dict(offset=math.nan), "offset", "nan"),
        (dict(angle=math.inf), "angle", "inf"),
        (dict(slope=math.nan), "slope", "nan"),
        (dict(EA=0.0), "EA", "0.0"),
        (dict(EA=math.nan), "EA", "nan"),
        (dict(end=0.0), "end", "0.0"),
        (dict(end=-0.1), "end", "-0.1"),
        (dict(pretension=-1.0), "pretension", "-1.0"),
        (dict(pretension=math.inf), "pretension", "inf"),
    ],
)
def test_tendon_validation_names_field_and_value(kw, field, value):
    with pytest.raises(ValueError) as e:
        tr.Tendon(**{"offset": 0.01, **kw})
    assert f"Tendon.{field}" in str(e.value) and value in str(e.value)


def test_tendon_without_an_offset_warns():
    # the 0.01 m default goes away: a FutureWarning now (an error from tendonrod 0.2)
    with pytest.warns(FutureWarning, match="offset="):
        t = tr.Tendon(angle=0.5)
    assert t.offset == 0.01
    # a path gives the offset; the constructors take it as an argument
    assert tr.Tendon.converging(offset=0.02, length=0.2).offset == 0.02


def test_converging_tendon():
    t = tr.Tendon.converging(offset=0.01, angle=0.5, length=0.2)
    assert t.slope == -0.01 / 0.2 and t.offset == 0.01 and t.angle == 0.5
    assert t.radius(0.2) == pytest.approx(0.0, abs=1e-18)  # round-off of b - b/L*L
    tr.Robot(tr.Rod(**ROD), [t])  # ends exactly on the centre line: legal
    with pytest.raises(TypeError):
        tr.Tendon.converging(offset=0.01)


def test_robot_checks_end_and_routing():
    rod = tr.Rod(**ROD)
    assert tr.Robot(rod, []).n_tendons == 0
    with pytest.raises(ValueError, match=r"tendons\[1\]\.end.*0\.3"):
        tr.Robot(rod, [tr.Tendon(offset=0.01), tr.Tendon(offset=0.01, end=0.3)])
    # a slope that reaches the centre line at 0.1 m on a 0.2 m rod crosses it before the tip
    with pytest.raises(ValueError, match=r"tendons\[0\].*centre line"):
        tr.Robot(rod, [tr.Tendon(offset=0.01, slope=-0.1)])
    # ... but is fine when anchored at 0.1 m; Tendon.converging anchors it there by default
    tr.Robot(rod, [tr.Tendon(offset=0.01, slope=-0.1, end=0.1)])
    assert tr.Robot(rod, [tr.Tendon.converging(offset=0.01, length=0.1)]).tendon_end(0) == 0.1
    with pytest.raises(ValueError, match="tendons\\[0\\] must be a tendonrod.Tendon"):
        tr.Robot(rod, ["tendon"])


def test_pretension_rules():
    rod = tr.Rod(**ROD)
    kir = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    pair = [
        tr.Tendon(offset=0.01, pretension=2.0),
        tr.Tendon(offset=0.01, angle=np.pi, pretension=2.0),
    ]
    tr.Robot(rod, pair)  # balanced, Cosserat backbone
    three = [
        tr.Tendon(offset=0.01, angle=2 * np.pi * i / 3, EA=1e4, pretension=1.0) for i in range(3)
    ]
    tr.Robot(kir, three)  # balanced, extensible tendons
    with pytest.raises(ValueError, match="not balanced"):
        tr.Robot(rod, [tr.Tendon(offset=0.01, pretension=2.0)])
    with pytest.raises(ValueError, match="not balanced"):
        tr.Robot(
            rod,
            [
                tr.Tendon(offset=0.01, pretension=2.0),
                tr.Tendon(offset=0.01, angle=np.pi, pretension=1.0),
            ],
        )
    with pytest.raises(ValueError, match="axial compliance"):
        tr.Robot(kir, pair)


def test_scene_actuation_rules():
    rod = tr.Rod(**ROD)
    rob = tr.Robot(rod, [tr.Tendon(offset=0.01), tr.Tendon(offset=0.01, angle=np.pi)])
    sc = tr.Scene(rob, displacement=[1e-3, None], tension=[None, 2.0])
    assert sc.displacement_controlled() == (True, False)
    with pytest.raises(ValueError, match="tendon 1 has neither"):
        tr.Scene(rob, displacement=[1e-3, None], tension=[None, None])
    with pytest.raises(ValueError, match=r"tendon 0 has both displacement\[0\]=0.001"):
        tr.Scene(rob, displacement=[1e-3, None], tension=[1.0, 2.0])
    with pytest.raises(ValueError, match="one entry per tendon"):
        tr.Scene(rob, displacement=[1e-3])
    with pytest.raises(ValueError, match=r"tension\[1\] must be >= 0.*-2.0"):
        tr.Scene(rob, displacement=[1e-3, None], tension=[None, -2.0])
    with pytest.raises(ValueError, match=r"displacement\[0\].*nan"):
        tr.Scene(rob, displacement=[math.nan, None], tension=[None, 1.0])
    tr.Scene(tr.Robot(rod, []))  # no tendons: lists may be omitted
    kir = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    with pytest.raises(
        ValueError, match=r"displacement\[0\]=0.0: tendon 0 runs on the centre line"
    ):
        tr.Scene(tr.Robot(kir, [tr.Tendon(offset=0.0)]), displacement=[0.0])
    tr.Scene(tr.Robot(kir, [tr.Tendon(offset=0.0)]), tension=[1.0])  # a tension can act
    tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.0)]), displacement=[1e-4])  # backbone compresses


def test_loads_validation_and_packing():
    rod = tr.Rod(**ROD)
    rob = tr.Robot(
        rod,
        [
            tr.Tendon.converging(offset=0.01, length=0.2),
            tr.Tendon(offset=0.01, angle=np.pi, end=0.1),
        ],
    )
    with pytest.raises(ValueError, match=r"loads\[0\]\.s.*0\.25"):
        tr.Scene(rob, displacement=[0, 0], loads=[tr.PointLoad(s=0.25, force=(1, 0, 0))])
    with pytest.raises(ValueError, match=r"PointLoad\.force.*3-vector"):
        tr.PointLoad(s=0.1, force=(1, 0))
    with pytest.raises(ValueError, match=r"PointLoad\.moment.*finite"):
        tr.PointLoad(s=0.1, moment=(1, math.nan, 0))
    with pytest.raises(ValueError, match=r"PointLoad\.s.*-0\.1"):
        tr.PointLoad(s=-0.1)
    with pytest.raises(ValueError, match=r"DistributedLoad\.force"):
        tr.DistributedLoad(force=(0, 0, math.inf))
    with pytest.raises(ValueError, match=r"loads\[1\] must be a PointLoad"):
        tr.Scene(rob, displacement=[0, 0], loads=[tr.PointLoad(s=0.1), (0, 0, 1)])
    sc = tr.Scene(
        rob,
        displacement=[2e-3, None],
        tension=[None, 1.5],
        loads=[
            tr.PointLoad(s=0.2, force=(1, 2, 3), moment=(4, 5, 6)),
            tr.DistributedLoad(force=(0, 0, -0.1)),
            tr.DistributedLoad(force=(0.05, 0, 0)),
        ],
    )
    rod_a, ten, lds, dist = pack_scene(sc)
    np.testing.assert_array_equal(
        rod_a,
        [
            0.2,
            rod.bending_stiffness,
            rod.torsional_stiffness,
            rod.axial_stiffness,
            rod.shear_stiffness,
            0.0,
        ],
    )
    np.testing.assert_array_equal(ten[0], [0.01, 0.0, -0.01 / 0.2, np.inf, 0.2, 0.0, 2e-3, 0.0])
    np.testing.assert_array_equal(ten[1], [0.01, np.pi, 0.0, np.inf, 0.1, 1.0, 1.5, 0.0])
    np.testing.assert_array_equal(lds, [[0.2, 1, 2, 3, 4, 5, 6]])
    np.testing.assert_array_equal(dist, [0.05, 0, -0.1])
    assert ten.dtype == np.float64 and ten.shape == (2, 8) and lds.shape == (1, 7)


@pytest.mark.parametrize(
    "kw, field",
    [
        (dict(integrator="euler"), "integrator"),
        (dict(steps=-1), "steps"),
        (dict(steps=2.5), "steps"),
        (dict(tol=0.0), "tol"),
        (dict(rtol=math.nan), "rtol"),
        (dict(max_iter=0), "max_iter"),
        (dict(jacobian_method="sensitivity"), "jacobian_method"),
        (dict(slack_model="cubic"), "slack_model"),
        (dict(nodes=1), "nodes"),
        (dict(nodes=[0.1, 0.05]), "nodes"),
        (dict(continuation="yes"), "continuation"),
        (dict(shooting_segments=0), "shooting_segments"),
    ],
)
def test_options_validation(kw, field):
    with pytest.raises(ValueError, match=f"Options.{field}"):
        tr.Options(**kw)


def test_options_defaults_and_raw():
    o = tr.Options()
    raw = o.raw()
    assert raw["integrator"] == "rk8" and raw["nodes"] == 101 and raw["tol"] == 1e-10
    o2 = tr.Options(nodes=[0.0, 0.1, 0.2])
    assert isinstance(o2.nodes, np.ndarray) and o2 == tr.Options(nodes=np.array([0.0, 0.1, 0.2]))
    assert hash(o2) == hash(tr.Options(nodes=(0.0, 0.1, 0.2)))
    assert dataclasses.replace(o, steps=8).steps == 8


def test_solve_rejects_bad_input_before_c():
    rod = tr.Rod(**ROD)
    sc = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), displacement=[0.0])
    with pytest.raises(ValueError, match="scene must be a tendonrod.Scene"):
        tr.solve("scene")
    with pytest.raises(ValueError, match="options must be"):
        tr.solve(sc, options=3)
    with pytest.raises(ValueError, match=r"guess must be a finite array of shape \(8,\)"):
        tr.solve(sc, guess=np.zeros(5))
    with pytest.raises(ValueError, match=r"Options.nodes must lie in \[0, L"):
        tr.solve(sc, options=tr.Options(nodes=[0.0, 0.3]))
    # the compliance point lies in (0, L]: at s = 0 the clamp takes any load
    with pytest.raises(ValueError, match=r"s must be an arc length in \(0, L"):
        tr.compliance(sc, s=0.5)
    with pytest.raises(ValueError, match=r"s must be an arc length in \(0, L"):
        tr.compliance(sc, s=0.0)


@pytest.mark.parametrize(
    "make, field",
    [
        (lambda: tr.Rod(length=10**400, diameter=1e-3, E=1e9, G=1e9), "Rod.length"),
        (lambda: tr.Tendon(offset=10**400), "Tendon.offset"),
        (lambda: tr.PointLoad(s=0.1, force=(10**400, 0, 0)), "PointLoad.force"),
        (lambda: tr.PointLoad(s=0.1, force=np.array([1 + 1j, 0, 0])), "PointLoad.force"),
        (lambda: tr.DistributedLoad(force=np.array([1j, 0, 0])), "DistributedLoad.force"),
        (lambda: tr.Rod(length=0.2, diameter=1e100, E=1e9, G=1e9), "Rod.EI"),
        (lambda: tr.Rod(length=0.2, diameter=1e-90, E=1e9, G=1e9), "Rod.EI"),
        (lambda: tr.Rod(length=0.2, diameter=8e-4, E=1e-320, G=1e9), "Rod.EI"),
        (lambda: tr.Options(integrator=np.array(["rk8"])), "Options.integrator"),
        (lambda: tr.Options(slack_model=np.zeros(2)), "Options.slack_model"),
    ],
)
def test_overflow_underflow_complex_and_array_inputs_are_value_errors(make, field):
    """Reliability findings F3-F6: every refusal is a ValueError naming the field."""
    with pytest.raises(ValueError, match=field.replace(".", r"\.")):
        make()
