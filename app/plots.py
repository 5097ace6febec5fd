"""Live plots (uPlot): theta(t), |K|(t) and E(t), and theta(t) with a cheaper fidelity's prediction.

Each plot is fed from the engine's ring buffer, so the window and the memory stay bounded. The
prediction has its own chart, shown instead of the plain theta chart while an overlay is chosen
(toggling a chart's visibility is more robust in the browser than changing its series).
"""

from __future__ import annotations

import numpy as np

PLOT_HZ = 15.0  # plots resend their arrays; a quarter of the frame rate is smooth enough


def _series(label: str, color: str, dash: bool = False) -> dict:
    s = {"label": label, "stroke": color, "width": 2}
    if dash:
        s["dash"] = [6, 4]
    return s


def build_plots(gui, data: tuple[np.ndarray, ...]) -> dict:
    """Four uPlot charts; returns name -> handle."""
    t, theta, over, K, E = data
    x = {"label": "t (s)"}
    scales = {"x": {"time": False}}
    return {
        "theta": gui.add_uplot(data=(t, theta), series=(x, _series("theta (rad)", "#1f77b4")), scales=scales,
                               title="nutation angle theta", aspect=2.2),
        "overlay": gui.add_uplot(data=(t, theta, over), series=(x, _series("theta (rad)", "#1f77b4"),
                                                                _series("prediction", "#d62728", dash=True)),
                                 scales=scales, title="theta and the cheaper model's prediction", aspect=2.2,
                                 visible=False),
        "K": gui.add_uplot(data=(t, K), series=(x, _series("|K| (kg m^2/s)", "#2ca02c")), scales=scales,
                           title="|K|", aspect=3.5),
        "E": gui.add_uplot(data=(t, E), series=(x, _series("E (J)", "#ff7f0e")), scales=scales, title="energy E",
                           aspect=3.5),
    }


def update_plots(handles: dict, data: tuple[np.ndarray, ...], overlay: bool = False) -> None:
    t, theta, over, K, E = data
    if len(t) < 2:
        return
    if handles["overlay"].visible != overlay:
        handles["overlay"].visible = overlay
        handles["theta"].visible = not overlay
    if overlay:
        handles["overlay"].data = (t, theta, over)
    else:
        handles["theta"].data = (t, theta)
    handles["K"].data = (t, K)
    handles["E"].data = (t, E)
