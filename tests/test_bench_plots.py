"""The benchmark charts' layout, drawn from the committed results (bench/results/)."""

import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402
from test_plot import layout_problems  # noqa: E402

from tendonrod.bench import plots  # noqa: E402
from tendonrod.bench import work_precision as wp  # noqa: E402
from tendonrod.bench.common import read_csv  # noqa: E402

RESULTS = pathlib.Path(__file__).resolve().parents[1] / "bench" / "results"


def _rows():
    rows = []
    for r in read_csv(RESULTS / "work_precision.csv"):
        r = dict(r)
        r["success"] = r["success"] == "True"
        for k in ("error", "seconds"):
            r[k] = float(r[k]) if r[k] not in ("", None) else math.nan
        rows.append(r)
    return rows


@pytest.mark.skipif(not (RESULTS / "work_precision.csv").exists(), reason="no recorded run")
def test_work_precision_chart_layout():
    """The committed run's chart: no tick labels overlapping (the log axes' minor labels
    did, on axes spanning under a decade), nothing outside the figure, and one legend of
    the encodings (methods, Jacobians, failure) whose entries all draw something, not
    one entry per combination (19 before)."""
    rows = _rows()
    names = {r["scene"] for r in rows}
    scenes = [s for s in wp.wp_scenes() if s.name in names]
    fig = plots.work_precision_figure(rows, scenes)
    try:
        assert layout_problems(fig) == []
        (legend,) = fig.legends
        labels = [t.get_text() for t in legend.get_texts()]
        methods = {r["method"] for r in rows}
        # one entry per method, per Jacobian and slack form, and the failure marker
        assert len(labels) <= len(methods) + 5, labels
        for h in legend.legend_handles:
            assert h.get_linestyle() not in ("None", "", " ") or h.get_marker() != "None"
    finally:
        plt.close(fig)
