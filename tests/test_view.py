"""tr.plot.view: the traces it draws (the tube at the rod's radius, tendon colours by
tension, load arrows at their scale, frames and steps), and the standalone page in a real
browser (headless Chromium driven by Selenium: no console error, the expected traces, the
slider's animation moves the robot)."""

import math
import os
import shutil
import sys

import numpy as np
import plotly.colors
import pytest

import tendonrod as tr

D = 0.8e-3  # backbone diameter [m]
L = 0.2


def _rod():
    return tr.Rod(length=L, diameter=D, E=207e9, G=79.6e9, kirchhoff=True, density=7850.0)


def _robot(**kw):
    # two stretchable tendons (EA = 50 N) on opposite sides: a path in displacement[0]
    return tr.Robot(_rod(), [tr.Tendon(0.01, 0.0, EA=50.0), tr.Tendon(0.01, np.pi, EA=50.0)], **kw)


@pytest.fixture(scope="module")
def sol():
    # tendon 0 pulled, tendon 1 paid out (slack), a tip load and gravity on 4 disk masses
    scene = tr.Scene(
        _robot(),
        displacement=[0.01, -0.02],
        loads=[
            tr.PointLoad(s=L, force=(0.0, 0.05, -0.1)),
            *tr.PointMass.disks([0.05, 0.1, 0.15, 0.2], 1e-3),
        ],
        gravity=(0.0, 0.0, -9.81),
    )
    s = tr.solve(scene)
    assert s.success and s.tension[0] > 0 and s.tension[1] == 0 and s.slack[1] > 0
    return s


@pytest.fixture(scope="module")
def path():
    scene = tr.Scene(
        _robot(), displacement=[0.0, 0.0], loads=[tr.PointLoad(s=L, force=(0, 0.1, 0))]
    )
    p = tr.path(scene, "displacement[0]", (0.0, 0.0157))
    assert p.success and len(p) > 3
    return p


def _by_name(fig, name):
    return [t for t in fig.data if t.name == name]


def _mesh_vertices(t):
    return np.stack([np.asarray(t.x), np.asarray(t.y), np.asarray(t.z)], axis=-1)


def test_traces_of_a_solution(sol):
    fig = tr.plot.view(sol)
    names = [t.name for t in fig.data]
    assert names == [
        "backbone (d = 0.8 mm)",
        "disks",
        "tendon 0",
        "tendon 1",
        "loads (1 N = 447 mm)",  # the largest force, |(0, 0.05, -0.1)| = 0.1118 N, L/4 long
        "load heads",
        *["world frame"] * 3,
        "gravity (9.81 m/s²)",
        "gravity head",
    ]
    assert not fig.frames


def test_tube_radius_is_half_the_diameter(sol):
    tube = _by_name(fig := tr.plot.view(sol, sides=16), "backbone (d = 0.8 mm)")[0]
    V = _mesh_vertices(tube)[:-2]  # the last two vertices are the end caps' centres
    P = np.asarray(sol.position)
    dist = np.min(np.linalg.norm(V[:, None, :] - P[None, :, :], axis=-1), axis=1)
    # each ring vertex sits at the radius from its node; every other node is farther
    # (sqrt(r^2 + h^2 (1 - r kappa)) > r); rounding of 0.2 m coordinates: ~1e-17 m
    np.testing.assert_allclose(dist, D / 2, rtol=1e-9)
    # one ring per node; a node repeated at a breakpoint (the point masses') only once
    assert len(V) == 16 * len(np.unique(sol.s)) < 16 * len(P)
    assert fig.layout.scene.aspectmode == "cube"


def _luminance(rgb):
    r, g, b = (int(c) / 255 for c in rgb.strip("rgb()").split(","))
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def test_tendon_colour_is_its_tension_and_monotone(sol, path):
    fig = tr.plot.view(sol)
    t0, t1 = _by_name(fig, "tendon 0")[0], _by_name(fig, "tendon 1")[0]
    # frictionless tendons: the tension is the same all along (the solution's tension)
    np.testing.assert_allclose(t0.line.color, sol.tension[0], rtol=1e-12)
    np.testing.assert_array_equal(t1.line.color, 0.0)
    assert t0.line.dash == "solid" and t1.line.dash == "dash"  # tendon 1 is slack
    # along a load path the tensions change: the drawn colour's lightness rises with them
    fig = tr.plot.view(path)
    pairs = []
    for fr in fig.frames:
        for t in fr.data:
            if t.name and t.name.startswith("tendon"):
                c = float(np.asarray(t.line.color)[0])
                frac = (c - t.line.cmin) / (t.line.cmax - t.line.cmin)
                assert 0.0 <= frac <= 1.0
                rgb = plotly.colors.sample_colorscale([list(p) for p in t.line.colorscale], [frac])[
                    0
                ]
                pairs.append((c, _luminance(rgb)))
    pairs.sort()
    assert pairs[-1][0] > pairs[0][0] + 0.1  # the path spans some tension
    lum = [p[1] for p in pairs]
    assert all(b >= a - 1e-12 for a, b in zip(lum, lum[1:]))
    assert lum[-1] > lum[0] + 0.5


@pytest.mark.parametrize("scale", [None, 0.05])
def test_arrow_length_is_scale_times_force(sol, scale):
    fig = tr.plot.view(sol, load_scale=scale)
    k = fig.layout.meta["tendonrod_load_scale"]
    F = np.array([0.0, 0.05, -0.1])
    if scale is None:
        assert k * np.linalg.norm(F) == pytest.approx(L / 4, rel=1e-12)  # the default
    else:
        assert k == scale and "1 N = 50 mm" in fig.layout.title.text
    shaft = _mesh_vertices(next(t for t in fig.data if t.name.startswith("loads")))
    head = _mesh_vertices(_by_name(fig, "load heads")[0])
    tail = shaft[0]
    apex = head[np.argmax(np.linalg.norm(head - tail, axis=1))]
    # the arrow ends at the load's point (the tip) and points along the force
    np.testing.assert_allclose(apex, sol.position[-1], atol=1e-12)
    np.testing.assert_allclose(apex - tail, k * F, atol=1e-12)


def test_mounted_robot_shows_its_base_frame():
    R0 = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])  # rod along world -y
    s = tr.solve(
        tr.Scene(_robot(base_position=(0.1, 0, 0), base_rotation=R0), displacement=[0.0, 0.0])
    )
    fig = tr.plot.view(s)
    base = _by_name(fig, "base frame")
    assert len(base) == 3
    z_axis = _mesh_vertices(base[2])
    np.testing.assert_allclose(z_axis[0], (0.1, 0, 0))
    np.testing.assert_allclose(z_axis[1] - z_axis[0], 0.1 * L * R0[:, 2], atol=1e-15)


def test_path_steps_are_its_points(path):
    fig = tr.plot.view(path)
    assert len(fig.frames) == len(path) == len(fig.layout.sliders[0].steps)
    for i, fr in enumerate(fig.frames):
        tube = _mesh_vertices(fr.data[0])
        # the tip cap's centre (the last vertex) is the point's tip, recorded again from
        # its converged unknowns at its step count: the path's own tip to rounding
        np.testing.assert_allclose(tube[-1], path.tip_position[i], atol=1e-13)
    fig = tr.plot.view(path, max_frames=4)
    assert len(fig.frames) == 4


def test_sweep_needs_its_scene_and_resolves_each_point():
    scene = tr.Scene(_robot(), displacement=[0.0, 0.0])
    res = tr.sweep(scene, {"displacement[0]": [0.0, 0.005, 0.01]})
    with pytest.raises(ValueError, match="scene="):
        tr.plot.view(res)
    fig = tr.plot.view(res, scene)
    assert [s.label for s in fig.layout.sliders[0].steps] == [
        "displacement[0] = 0",
        "displacement[0] = 0.005",
        "displacement[0] = 0.01",
    ]
    tips = np.array([_mesh_vertices(fr.data[0])[-1] for fr in fig.frames])
    # solved again, warm, to the solver's tolerance (1e-10 scaled): within 1e-9 m of the
    # sweep's own tips
    np.testing.assert_allclose(tips, res["tip_position"], atol=1e-9)


def test_bad_input_and_missing_plotly(sol, monkeypatch):
    with pytest.raises(ValueError, match="Solution"):
        tr.plot.view(42)
    with pytest.raises(ValueError, match="load_scale"):
        tr.plot.view(sol, load_scale=-1.0)
    with pytest.raises(ValueError, match="max_frames"):
        tr.plot.view([sol, sol], max_frames=0)
    monkeypatch.setitem(sys.modules, "plotly", None)
    monkeypatch.setitem(sys.modules, "plotly.graph_objects", None)
    with pytest.raises(ImportError, match=r"tendonrod\[view\]"):
        tr.plot.view(sol)


# --------------------------------------------------------------------------- the browser
_BROWSER = shutil.which("chromium") and shutil.which("chromedriver")


@pytest.mark.skipif(
    not _BROWSER, reason="no chromium/chromedriver: run tools/browser.sh to install them"
)
def test_page_in_headless_chromium(tmp_path, path):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    fig = tr.plot.view(path, max_frames=6)
    page = tmp_path / "view.html"
    tr.plot.save_html(fig, page)
    assert "cdn.plot.ly" not in page.read_text()[:2000]  # plotly.js inlined, not fetched
    opts = webdriver.ChromeOptions()
    # headless, as root in a container, WebGL from the software rasteriser
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-dev-shm-usage",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--window-size=1000,800",
    ):
        opts.add_argument(arg)
    opts.binary_location = shutil.which("chromium")
    opts.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    # the browser gets the environment without LD_PRELOAD: the sanitizer run preloads the
    # ASan runtime into Python, and Chromium must not inherit it
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    service = Service(shutil.which("chromedriver"), env=env)
    driver = webdriver.Chrome(service=service, options=opts)
    try:
        driver.set_script_timeout(60)
        driver.get(page.as_uri())
        got = driver.execute_script(
            "const gd = document.querySelector('.js-plotly-plot');"
            "return [gd.data.map(t => t.name), gd._transitionData._frames.length,"
            " document.querySelectorAll('.gl-container canvas').length];"
        )
        tip = driver.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "const gd = document.querySelector('.js-plotly-plot');"
            "const tip = () => { const t = gd._fullData[0];"
            "  const n = t.x.length - 1; return [t.x[n], t.y[n], t.z[n]]; };"
            "const before = tip(); const fr = gd._transitionData._frames;"
            "Plotly.animate(gd, [fr[fr.length - 1].name],"
            "  {frame: {duration: 0, redraw: true}, mode: 'immediate', transition: {duration: 0}})"
            ".then(() => done([before, tip()])).catch(e => done(String(e)));"
        )
        log = driver.get_log("browser")
    finally:
        driver.quit()
    names, nframes, canvases = got
    assert names == [t.name for t in fig.data]
    assert names[:5] == ["backbone (d = 0.8 mm)", "tendon 0", "tendon 1"] + names[3:5]
    assert nframes == len(fig.frames) == 6 and canvases >= 1  # a WebGL scene was drawn
    # the slider's last step shows the path's last point
    np.testing.assert_allclose(tip[0], path.tip_position[0], atol=1e-12)
    np.testing.assert_allclose(tip[1], path.tip_position[-1], atol=1e-12)
    errors = [e for e in log if e["level"] == "SEVERE"]
    assert not errors, errors


def test_arrow_geometry():
    from tendonrod._view import arrow

    shaft, head = arrow((1.0, 2.0, 3.0), (0.0, 0.3, -0.4))
    apex = head.vertices[np.argmax(np.linalg.norm(head.vertices - shaft[0], axis=1))]
    np.testing.assert_allclose(apex, (1.0, 2.3, 2.6), atol=1e-15)
    # the shaft ends where the head begins, a quarter of the length before the apex
    assert math.dist(shaft[1], apex) == pytest.approx(0.25 * 0.5, rel=1e-12)
