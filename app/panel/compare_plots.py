"""Compare mode's charts: theta, |K| and E of both runs overlaid in two colours, each series named by the
difference ("theta, m = 0.2 kg" against "theta, m = 0 kg") in uPlot's legend. Shown instead of the single
run's charts while compare mode is on (toggling visibility is more robust in the browser than changing a
chart's series: app.panel.plots), on the same axes settings and y scales (app.panel.plot_scale).
"""

from __future__ import annotations

import numpy as np

from ..engine.compare import Comparison
from .plot_scale import ScaleKeeper, y_range
from .plots import CHARTS, PAD_TOP_PX, _axes

SECOND = "#e8822f"  # the second run: orange, as its body is drawn (app.scene.compare_view)


class ComparePlots:
    """Three hidden uPlot charts, each with both runs' series."""

    def __init__(self, gui, data: tuple[np.ndarray, ...]):
        t, theta, _, K, E = data
        kw = {"scales": {"x": {"time": False}}, "axes": _axes(), "padding": (PAD_TOP_PX, 28, 0, 0)}
        self.handles = {}
        self.keepers = {name: ScaleKeeper() for name in CHARTS}
        self._names: tuple[str, str] | None = None
        self._scales: dict = {}
        self.shown = False
        for name, y in (("theta", theta), ("K", K), ("E", E)):
            title, symbol, unit, color = CHARTS[name]
            series = ({"label": "t (s)"}, {"label": symbol, "stroke": color, "width": 2},
                      {"label": symbol, "stroke": SECOND, "width": 2, "dash": [6, 3]})
            self.handles[name] = gui.add_uplot(data=(t, y, y), series=series, title=f"{title}: both runs",
                                               aspect=2.2 if name == "theta" else 3.0, visible=False, **kw)

    def update(self, eng, charts) -> bool:
        """Draw both runs when compare mode is on (and hide ``charts``, the single run's); when it has just
        been turned off, show ``charts`` again. Returns whether compare mode drew (the caller then skips
        ``charts``)."""
        c = eng.compare
        on = isinstance(c, Comparison)
        if on != self.shown:
            self.shown = on
            for h in self.handles.values():
                h.visible = on
            for name, h in charts.handles.items():  # the overlay chart shows again with its next update
                h.visible = not on and name != "overlay"
            if not on:
                return False
        if not on:
            return False
        t, theta, _, K, E = eng.plot_data()
        if len(t) < 2:
            return True
        names = (c.diff.own_label(eng.scenario), c.diff.label())
        theta2, K2, E2 = c.series(eng.plot_span, t)
        for name, a, b in (("theta", theta, theta2), ("K", K, K2), ("E", E, E2)):
            self._draw(name, names, t, a, b)
        self._names = names
        return True

    def _draw(self, name: str, names: tuple[str, str], t: np.ndarray, a: np.ndarray, b: np.ndarray) -> None:
        h = self.handles[name]
        _, symbol, unit, _ = CHARTS[name]
        keeper = self.keepers[name]
        if keeper.update(a, b) or names != self._names:  # a new scale or another difference: rename the series
            s = list(h.series)
            shown = keeper.scale.label(symbol, unit)  # "E (J)", "|K| − 3 (kg m²/s)": the scale both share
            s[1] = {**s[1], "label": f"{names[0]}: {shown}"}
            s[2] = {**s[2], "label": f"{names[1]}: {shown}"}
            h.series = tuple(s)
        ya, yb = keeper.scale.apply(a), keeper.scale.apply(b)
        h.data = (t, ya, yb)
        lo, hi = float(min(ya.min(), yb.min())), float(max(ya.max(), yb.max()))
        scales = {"x": {"time": False, "range": (float(t[0]), float(max(t[-1], t[0] + 1e-9)))},
                  "y": {"range": y_range(lo, hi)}}
        if scales != self._scales.get(name):
            self._scales[name] = scales
            h.scales = scales
