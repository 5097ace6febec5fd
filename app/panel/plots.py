"""Live plots (uPlot): theta(t), |K|(t) and E(t), and theta(t) with a cheaper fidelity's prediction.

The engine feeds them the whole run (decimated, app.engine.history) or the last few seconds played, as the
"plots show" dropdown says. Each chart's y values go through an ``app.panel.plot_scale`` scale, so that its
tick labels are short, exact and distinct, and its y axis is wide enough for the longest label such a
scale allows: uPlot draws tick labels on a canvas, right-aligned in an axis of fixed width, and cuts what
does not fit ("309.34" showed as "09.34"). The prediction has its own chart, shown instead of the plain
theta chart while an overlay is chosen (toggling a chart's visibility is more robust in the browser than
changing its series).
"""

from __future__ import annotations

import numpy as np

from ..engine.clock import FRAME_HZ
from ..engine.engine import PLOT_POINTS, RECENT, SAMPLES_PER_FRAME, WHOLE_RUN
from .plot_scale import ScaleKeeper, y_range

# uPlot's axis font; the y axis is as wide as its longest label allows: app.panel.plot_scale bounds a label to 7
# characters ("-99,990", "-0.075"), 7 * 7 px at 12 px, plus the tick and the gap (measured: see
# tests/test_app_browser_plots.py, which reads the drawn labels back)
AXIS_FONT = "12px sans-serif"
Y_AXIS_PX = 66
TICK_PX = 5
PAD_TOP_PX = 8  # the top tick's label is centred on the plot's top edge: room for its upper half
X_AXIS_PX = 34  # tick, gap and one line of labels: uPlot's default of 50 leaves a small chart little plot
Y_TICK_SPACE_PX = 15  # px between y ticks at least: a small chart's 60 px of plot show 3 or 4 (default 30: 1)
# tick steps uPlot may choose: 1, 2, 5 times a power of ten, none finer than 0.001 (uPlot prints 3
# decimals, so 0.0025 would print as "0.003" and 1e-4 steps as repeats of one label)
INCRS = [m * 10.0**k for k in range(-3, 16) for m in (1, 2, 5)]
RECENT_S = PLOT_POINTS / (SAMPLES_PER_FRAME * FRAME_HZ)  # wall seconds the "recent" window holds
SPANS = {"whole run": WHOLE_RUN, f"the last {RECENT_S:.0f} s played": RECENT}  # dropdown label -> engine's span

# name -> (title, symbol, unit, colour)
CHARTS = {
    "theta": ("nutation angle theta", "theta", "rad", "#1f77b4"),
    "K": ("angular momentum |K|", "|K|", "kg m²/s", "#2ca02c"),
    "E": ("energy E", "E", "J", "#ff7f0e"),
}
PREDICTION = "#d62728"


def _series(label: str, color: str, dash: bool = False) -> dict:
    s = {"label": label, "stroke": color, "width": 2}
    if dash:
        s["dash"] = [6, 4]
    return s


def _axes() -> tuple[dict, dict]:
    common = {"font": AXIS_FONT, "incrs": INCRS, "ticks": {"size": TICK_PX}}
    return {**common, "size": X_AXIS_PX}, {**common, "size": Y_AXIS_PX, "space": Y_TICK_SPACE_PX}


class Charts:
    """The "plots show" dropdown and four uPlot charts, with one y scale each."""

    def __init__(self, gui, data: tuple[np.ndarray, ...]):
        t, theta, over, K, E = data
        x = {"label": "t (s)"}
        kw = {"scales": {"x": {"time": False}}, "axes": _axes(), "padding": (PAD_TOP_PX, 28, 0, 0)}
        self.span = gui.add_dropdown("plots show", list(SPANS), initial_value=next(iter(SPANS)),
                                     hint="the whole run from t = 0 (thinned to a bounded number of points), "
                                          "or the last seconds played at full resolution")
        self.keepers = {name: ScaleKeeper() for name in ("theta", "overlay", "K", "E")}
        self.overlay_title = "theta and the cheaper model's prediction"
        self.handles = {}
        self._scales: dict = {}  # name -> the scales last sent
        for name, y in (("theta", theta), ("K", K), ("E", E)):
            title, symbol, unit, color = CHARTS[name]
            self.handles[name] = gui.add_uplot(data=(t, y), series=(x, _series(f"{symbol} ({unit})", color)),
                                               title=title, aspect=2.2 if name == "theta" else 3.0, **kw)
            if name == "theta":
                self.handles["overlay"] = gui.add_uplot(
                    data=(t, theta, over),
                    series=(x, _series("theta (rad)", color), _series("prediction (rad)", PREDICTION, dash=True)),
                    title=self.overlay_title, aspect=2.2, visible=False, **kw)

    def update(self, data: tuple[np.ndarray, ...], overlay: bool = False, overlay_title: str = "") -> None:
        t, theta, over, K, E = data
        if len(t) < 2:
            return
        h = self.handles
        if h["overlay"].visible != overlay:
            h["overlay"].visible = overlay
            h["theta"].visible = not overlay
        if overlay:
            if overlay_title and overlay_title != h["overlay"].title:
                h["overlay"].title = overlay_title
            scale = self._rescale("overlay", theta, over)
            self._push("overlay", t, scale.apply(theta), scale.apply(over))
        else:
            self._push("theta", t, self._rescale("theta", theta).apply(theta))
        self._push("K", t, self._rescale("K", K).apply(K))
        self._push("E", t, self._rescale("E", E).apply(E))

    def _push(self, name: str, t: np.ndarray, *ys: np.ndarray) -> None:
        """The plotted arrays, and the axes' extents when they changed: x exactly the data's, y from
        plot_scale.y_range (uPlot's own x ranging drifts under viser's zoom keeping)."""
        handle = self.handles[name]
        handle.data = (t, *ys)
        lo, hi = min(float(np.min(y)) for y in ys), max(float(np.max(y)) for y in ys)
        scales = {"x": {"time": False, "range": (float(t[0]), float(max(t[-1], t[0] + 1e-9)))},
                  "y": {"range": y_range(lo, hi)}}
        if scales != self._scales.get(name):
            self._scales[name] = scales
            handle.scales = scales

    def _rescale(self, name: str, *ys: np.ndarray):
        """The chart's scale for these values; a new scale renames its series (the legend and the axis
        read "|K| - 3.58 (x1e-9 kg m²/s)")."""
        keeper = self.keepers[name]
        if keeper.update(*ys):
            _, symbol, unit, color = CHARTS["theta" if name == "overlay" else name]
            handle = self.handles[name]
            s = list(handle.series)
            s[1] = {**s[1], "label": keeper.scale.label(symbol, unit)}
            if name == "overlay":
                s[2] = {**s[2], "label": keeper.scale.label("prediction", unit)}
            handle.series = tuple(s)
        return keeper.scale


def build_plots(gui, data: tuple[np.ndarray, ...]) -> Charts:
    return Charts(gui, data)


def update_plots(charts: Charts, data: tuple[np.ndarray, ...], overlay: bool = False, overlay_title: str = "") -> None:
    charts.update(data, overlay, overlay_title)
