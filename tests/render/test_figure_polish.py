"""Figure polish (issue 35, item 5): each test guards one defect seen in the default run's
figures, measured on the drawn figure (text boxes in pixels, marker extents, pixel colours)."""

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg

from tensegrity.render import gravity


def test_slope_limit_markers_at_0_deg_lie_inside_the_axes():
    """The gravity-aware grid says 0 deg where the robot cannot stand: those markers sat on
    the lower spine, cut in half."""
    headings = np.arange(0.0, 360.0, 45.0)
    simulated = np.full((3, 2, 8), 12.0)
    grid = np.tile(np.array([0.0, 10.0, 0.0, 20.0, 0.0, 15.0, 0.0, 38.0]), (3, 2, 1))
    fig = gravity.slope_limit_axes(
        ["stand", "uphill", "downhill"], ["equilateral", "isosceles"], headings, simulated, simulated, grid, 38.7, 5.0
    )
    FigureCanvasAgg(fig).draw()
    checked = 0
    for ax in fig.axes:
        box = ax.bbox
        for line in ax.get_lines():
            if line.get_marker() in ("None", "", None):
                continue
            r = (line.get_markersize() + line.get_markeredgewidth()) / 2 * fig.dpi / 72  # px
            xy = ax.transData.transform(np.column_stack(line.get_data()))
            assert (xy[:, 0] - r >= box.x0).all() and (xy[:, 0] + r <= box.x1).all()
            assert (xy[:, 1] - r >= box.y0).all(), f"a marker of {line.get_label()!r} is cut by the lower spine"
            assert (xy[:, 1] + r <= box.y1).all()
            checked += int((line.get_ydata() == 0).sum())
    assert checked == 2 * 3 * 4  # every 0 deg marker of both panels was measured
