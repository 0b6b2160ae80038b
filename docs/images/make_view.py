"""The 3-D view's pictures in the guide (docs/guide/view.md): the standalone pages into
build/view/ and screenshots of them from headless Chromium into docs/images/.

    python docs/images/make_view.py        (needs plotly, selenium and tools/browser.sh)

:func:`figures` is also what ``make docs`` embeds as the guide's interactive pages
(docs/conf.py writes them into the HTML output's ``_static/``).
"""

import pathlib
import shutil

import numpy as np

import tendonrod as tr

HERE = pathlib.Path(__file__).parent
OUT = HERE.parents[1] / "build" / "view"
# the camera of the pictures and pages: from the side, a little above
CAMERA = dict(eye=dict(x=1.5, y=-1.3, z=0.7), center=dict(x=0, y=0, z=-0.1))


def figures() -> dict:
    """``{"view": fig, "view_path": fig}``: one solution and a load path of a NiTi tube, 2 mm
    across, with 10 spacer disks and three tendons 5 mm off the axis (tendon 0 pulled from
    0 to 40 N against a 0.3 N side load and gravity)."""
    rod = tr.Rod(length=0.2, diameter=2e-3, E=60e9, G=23e9, density=6450.0)
    tendons = [tr.Tendon(offset=0.005, angle=a) for a in (0.0, 2 * np.pi / 3, 4 * np.pi / 3)]
    robot = tr.Robot(rod, tendons)
    scene = tr.Scene(
        robot,
        tension=[0.0, 0.0, 0.0],  # N
        loads=[
            tr.PointLoad(s=0.2, force=(0.0, 0.3, 0.0)),
            *tr.PointMass.disks(np.linspace(0.02, 0.2, 10), 2e-3),
        ],
        gravity=(0.0, 0.0, -9.81),
    )
    path = tr.path(scene, "tension[0]", (0.0, 40.0))
    sol = tr.solve(path.scene_at(len(path) - 1))
    figs = {
        "view": tr.plot.view(sol, title=f"three tendons, tendon 0 at {sol.tension[0]:.3g} N"),
        "view_path": tr.plot.view(path, title="tendon 0's tension from 0 to 40 N"),
    }
    for fig in figs.values():
        fig.update_layout(scene_camera=CAMERA)
    return figs


def shot(fig, name: str) -> None:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    OUT.mkdir(parents=True, exist_ok=True)
    page = OUT / f"{name}.html"
    tr.plot.save_html(fig, page)
    opts = webdriver.ChromeOptions()
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-dev-shm-usage",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--window-size=1100,850",
        "--hide-scrollbars",
    ):
        opts.add_argument(arg)
    opts.binary_location = shutil.which("chromium")
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=opts)
    try:
        driver.get(page.as_uri())
        driver.set_script_timeout(60)
        # a load path's picture at its last step (the slider moved there)
        driver.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "const gd = document.querySelector('.js-plotly-plot');"
            "const fr = gd._transitionData._frames;"
            "if (!fr.length) { done(0); return; }"
            "Plotly.animate(gd, [fr[fr.length - 1].name], {frame: {duration: 0, redraw: true},"
            " mode: 'immediate', transition: {duration: 0}}).then(() => done(1));"
        )
        driver.save_screenshot(str(HERE / f"{name}.png"))
    finally:
        driver.quit()
    print(f"{page} ({page.stat().st_size / 1e6:.1f} MB), {HERE / (name + '.png')}")


if __name__ == "__main__":
    for name, fig in figures().items():
        shot(fig, name)
