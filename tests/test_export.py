"""Solution.export: each format read back by an independent reader (trimesh for the
meshes, numpy.loadtxt for the CSV, json for the JSON) and compared with the solution's
own arrays or with the tube's closed-form volume."""

import json
import math

import numpy as np
import pytest

import tendonrod as tr

trimesh = pytest.importorskip("trimesh")

D = 0.8e-3  # backbone diameter [m]
L = 0.2


def _rod():
    return tr.Rod(length=L, diameter=D, E=207e9, G=79.6e9, kirchhoff=True)


@pytest.fixture(scope="module")
def straight():
    return tr.solve(tr.Scene(tr.Robot(_rod(), [])))


@pytest.fixture(scope="module")
def bent():
    # one tendon pulled 15.7 mm: a bend of about 90 degrees (the Solution docstring's case)
    robot = tr.Robot(_rod(), [tr.Tendon(offset=0.01, angle=0.0), tr.Tendon(0.01, np.pi / 2)])
    return tr.solve(tr.Scene(robot, displacement=[0.0157, None], tension=[None, 0.5]))


def _polygon_area(n, r):
    # the inscribed regular n-gon: n triangles of area r^2 sin(2 pi / n) / 2
    return 0.5 * n * r * r * math.sin(2 * math.pi / n)


@pytest.mark.parametrize("suffix", [".obj", ".stl"])
@pytest.mark.parametrize("sides", [12, 48])
def test_straight_tube_closed_and_of_the_rod_volume(tmp_path, straight, suffix, sides):
    path = tmp_path / f"rod{suffix}"
    straight.export(path, sides=sides)
    m = trimesh.load(path, force="mesh")
    assert m.is_watertight and m.is_winding_consistent
    assert m.is_volume  # trimesh: watertight, consistent winding and outward normals
    prism = _polygon_area(sides, D / 2) * L  # the exact volume of the meshed prism
    # .obj keeps 17 digits: the prism's volume to rounding; .stl stores float32 vertices
    # (7 digits) of coordinates up to 0.2 m with a 0.4 mm radius: ~1e-7 m / 4e-4 m
    # relative in the radius, twice that in the area
    rtol = 1e-9 if suffix == ".obj" else 2e-3
    assert m.volume == pytest.approx(prism, rel=rtol)
    # against the round rod pi d^2 L / 4: short by the polygon's area deficit,
    # 1 - sin(2 pi/n) / (2 pi/n) (2.8 % at 12 sides, 0.18 % at 48)
    deficit = 1 - math.sin(2 * math.pi / sides) / (2 * math.pi / sides)
    exact = math.pi * D * D * L / 4
    assert exact * (1 - deficit - rtol) <= m.volume <= exact * (1 + rtol)


def test_normals_point_outward(tmp_path, straight):
    straight.export(tmp_path / "rod.obj", sides=16)
    m = trimesh.load(tmp_path / "rod.obj", force="mesh")
    c = m.triangles_center
    n = m.face_normals
    side = (c[:, 2] > 1e-9) & (c[:, 2] < L - 1e-9)
    # the rod lies on the z axis: a side face's normal points away from it, a cap's along
    # -z at the base and +z at the tip
    assert np.all(np.einsum("ij,ij->i", n[side, :2], c[side, :2]) > 0)
    assert np.all(n[c[:, 2] <= 1e-9, 2] < -0.99)
    assert np.all(n[c[:, 2] >= L - 1e-9, 2] > 0.99)


def test_bent_tube_keeps_the_tube_volume(tmp_path, bent):
    assert bent.success and abs(bent.tip_position[0]) > 0.1  # really bent
    sides = 48
    bent.export(tmp_path / "bent.obj", sides=sides)
    m = trimesh.load(tmp_path / "bent.obj", force="mesh")
    assert m.is_volume
    # Pappus: a tube of cross-section A swept along a curve of length L encloses A L while
    # r kappa << 1 (here r kappa ~ 4e-4 * 7.9 = 3e-3, its square 1e-5); the mesh follows
    # the chords between 101 nodes, short of the arc by (h kappa)^2 / 24 ~ 2.6e-5 with
    # h = 2 mm (4.2e-5 measured in all): bound 1e-4
    assert m.volume == pytest.approx(_polygon_area(sides, D / 2) * L, rel=1e-4)


def test_tendons_as_separate_closed_tubes(tmp_path, bent):
    bent.export(tmp_path / "with_tendons.stl", tendons=True, tendon_diameter=0.2e-3)
    m = trimesh.load(tmp_path / "with_tendons.stl", force="mesh")
    bodies = m.split(only_watertight=False)
    assert len(bodies) == 3  # the backbone and two tendons
    assert all(b.is_watertight and b.is_winding_consistent and b.volume > 0 for b in bodies)
    vols = sorted(b.volume for b in bodies)
    # a tendon's tube: its route is longer than L (offset 10 mm on a 90 degree bend) but
    # its cross-section is (0.2/0.8)^2 = 1/16 of the backbone's, meshed at 8 sides
    assert vols[-1] == pytest.approx(_polygon_area(32, D / 2) * L, rel=1e-3)
    assert vols[0] < vols[-1] / 10


def test_csv_columns_are_the_solution_arrays(tmp_path, bent):
    path = tmp_path / "bent.csv"
    bent.export(path)
    header = path.read_text().splitlines()[1]
    assert header.startswith("# s [m], x [m], y [m], z [m], R11 [-]")
    assert header.endswith("tension_0 [N], tension_1 [N]")
    t = np.loadtxt(path, delimiter=",")
    # %.17g round-trips a double exactly
    np.testing.assert_array_equal(t[:, 0], bent.s)
    np.testing.assert_array_equal(t[:, 1:4], bent.position)
    np.testing.assert_array_equal(t[:, 4:13].reshape(-1, 3, 3), bent.rotation)
    np.testing.assert_array_equal(t[:, 13:16], bent.force)
    np.testing.assert_array_equal(t[:, 16:19], bent.moment)
    np.testing.assert_array_equal(t[:, 19:], bent.tendon_tension)


def test_json_round_trip(tmp_path, bent):
    path = tmp_path / "bent.json"
    bent.export(path)
    doc = json.loads(path.read_text())
    assert doc["success"] is True and doc["units"]["moment"] == "N m"
    for key in ("s", "position", "rotation", "force", "moment", "tension", "tip_position"):
        np.testing.assert_array_equal(np.array(doc[key]), getattr(bent, key))
    assert doc["diameter"] == [D] * len(bent.s)


def test_unknown_suffix_is_named(tmp_path, straight):
    with pytest.raises(ValueError, match=r"'\.step'"):
        straight.export(tmp_path / "rod.step")
    with pytest.raises(ValueError, match="tendons"):
        straight.export(tmp_path / "rod.obj", tendons="yes")
    with pytest.raises(ValueError, match="sides"):
        straight.export(tmp_path / "rod.stl", sides=2)


def test_stepped_rod_closed_with_its_two_diameters(tmp_path):
    # a segmented rod, 2 mm then 1 mm across, unloaded (straight): the output repeats the
    # joint's node, where the tube steps from one radius to the other (a flat annulus)
    seg = tr.Rod.segmented(
        [
            tr.Rod(0.1, 2e-3, 60e9, 23e9, kirchhoff=True),
            tr.Rod(0.1, 1e-3, 60e9, 23e9, kirchhoff=True),
        ]
    )
    sol = tr.solve(tr.Scene(tr.Robot(seg, [])))
    sol.export(tmp_path / "stepped.obj", sides=24)
    m = trimesh.load(tmp_path / "stepped.obj", force="mesh")
    assert m.is_volume
    # two prisms: the exact volume of the mesh, to rounding
    prisms = (_polygon_area(24, 1e-3) + _polygon_area(24, 0.5e-3)) * 0.1
    assert m.volume == pytest.approx(prisms, rel=1e-9)
