"""The momentum sphere's companion chart (uPlot): E(t) with the energies of the pure spins about e1, e2, e3 at
the same |K| (K^2/2A, K^2/2B, K^2/2C), as dashed lines in the axes' colours. Dissipation at fixed |K| moves E
down towards K^2/(2 max(A, B, C)), the steady spin about the axis of largest moment; an intermediate-axis
flip keeps E between the lines of the other two. With braking, |K| falls and the lines fall with it.
A fifth line, E_end, is where the energy sink leads (physics.end_state: the largest moment of the system locked
in its end configuration, plus its spring's energy there); hidden when the scene has no fixed end (braking, a
medium, no dissipation).

Same axes, tick steps and server-sent ranges as the other charts (app.panel.plots, app.panel.plot_scale): one y
scale for all four series, since they are compared on one axis. Shown with the momentum sphere.
"""

from __future__ import annotations

import numpy as np

from ..engine.sphere import pure_spin_energies
from ..scene.legend import AXIS_COLORS
from .plot_scale import ScaleKeeper, y_range
from .plots import PAD_TOP_PX, _axes, _series

TITLE = "energy E and the pure spins"
E_COLOR = "#ff7f0e"  # as app.panel.plots' E chart
# the pure spins' series names (symbol, then what it is); the legend shows them with the chart's scale
SPINS = (("K²/2A", "spin about e1"), ("K²/2B", "spin about e2"), ("K²/2C", "spin about e3"))
END = ("E_end", "where the sink leads")
END_COLOR = "#9467bd"  # as the momentum sphere's end point (app.scene.sphere_view.END_COLOR)


def _hex(rgb) -> str:
    return "#" + "".join(f"{int(c):02x}" for c in rgb)


class EnergyChart:
    """One uPlot chart: E and the three pure spins' energies over the plots' span."""

    def __init__(self, gui, data: tuple[np.ndarray, ...], moments, visible: bool = True):
        t, E, spins = self._columns(data, moments)
        x_axis, y_axis = _axes()
        self.keeper = ScaleKeeper()
        self.keeper.update(E, *spins)
        series = [{"label": "t (s)"}, _series(self._label("E", ""), E_COLOR)]
        for (symbol, what), rgb in zip(SPINS, AXIS_COLORS, strict=True):
            series.append({**_series(self._label(symbol, what), _hex(rgb), dash=True), "width": 1.5})
        series.append({**_series(self._label(*END), END_COLOR), "width": 2.5, "show": False})
        data = (t, *self._apply(E, spins), self.keeper.scale.apply(E))  # E_end's line: E, hidden, until update
        self.handle = gui.add_uplot(data=data, series=tuple(series), title=TITLE, aspect=2.2,
                                    scales={"x": {"time": False}}, axes=(x_axis, y_axis),
                                    padding=(PAD_TOP_PX, 28, 0, 0), visible=visible)
        self._scales: dict = {}
        self._stale = True

    @staticmethod
    def _columns(data, moments):
        t, _, _, K, E = data
        return t, E, pure_spin_energies(K, moments)

    def _label(self, symbol: str, what: str) -> str:
        text = self.keeper.scale.label(symbol, "J")
        return f"{text}: {what}" if what else text

    def _apply(self, E, spins):
        s = self.keeper.scale
        return (s.apply(E), *(s.apply(y) for y in spins))

    def update(self, engine, changed: bool) -> None:
        """At the plots' rate: shown with the sphere; new data when the run moved (``changed``) or on showing."""
        shown = bool(getattr(engine, "show_sphere", True))
        if self.handle.visible != shown:
            self.handle.visible = shown
            self._stale = True
        if not shown or not (changed or self._stale):
            return
        b = engine.scenario.body
        # the same for every view of a class's frame (pure spins' energies along the whole run): computed once
        t, E, spins = engine.once_per_frame(
            "energy_columns", lambda: self._columns(engine.plot_data(), (b.A, b.B, b.C)))
        if len(t) < 2:
            return
        self._stale = False
        end = engine.end_state()
        line = np.full_like(E, end.E_end) if end else None
        renamed = self.keeper.update(E, *spins, *(() if line is None else (line,)))
        s = list(self.handle.series)
        if renamed:  # a new scale renames the series ("E − 5 (J)")
            s[1] = {**s[1], "label": self._label("E", "")}
            for i, (symbol, what) in enumerate(SPINS):
                s[2 + i] = {**s[2 + i], "label": self._label(symbol, what)}
            s[5] = {**s[5], "label": self._label(*END)}
        s[5] = {**s[5], "show": line is not None}
        if tuple(s) != tuple(self.handle.series):
            self.handle.series = tuple(s)
        ys = self._apply(E, spins)
        self.handle.data = (t, *ys, self.keeper.scale.apply(E if line is None else line))
        if line is not None:
            ys = (*ys, self.keeper.scale.apply(line))
        lo, hi = min(float(np.min(y)) for y in ys), max(float(np.max(y)) for y in ys)
        scales = {"x": {"time": False, "range": (float(t[0]), float(max(t[-1], t[0] + 1e-9)))},
                  "y": {"range": y_range(lo, hi)}}
        if scales != self._scales:
            self._scales = scales
            self.handle.scales = scales
