"""The sweep panel: pick one or two sliders, their ranges and a metric; the sweep runs in the background
on local worker processes (physics.sweep), with a progress bar, then shows the curve or heat map.

viser 1.1.1's plotly handle reports no clicks (GuiPlotlyHandle has no on_click). So the points are
also drawn in the 3-D scene as a board of cells beside the body (SweepBoard: colour and height by the
metric), and clicking a cell loads its scenario; a dropdown of the points, best first, with a "Load
this point" button does the same from the panel. Nothing here raises into viser: a failed sweep or an invalid
point becomes a message in the panel.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable

import numpy as np

import physics

from . import controls

NONE = "(none)"
NO_POINTS = "(run a sweep first)"
DEFAULT_POINTS = 8  # per parameter: 8 x 8 = 64 runs is a minute or so for the presets on two cores
MAX_POINTS = 60  # per parameter, so a misclick cannot queue thousands of runs
RANGE_FACTOR = 2.0  # the default range is value / 2 .. 2 value around the scenario's current value


def scenario_key(slider_key: str, system: str) -> str:
    """The scenario key a slider stands for: the pendulum sliders set every [[plane_pendulum]]."""
    if system == controls.PL and slider_key.startswith("pendulum."):
        return "plane_pendulum." + slider_key.split(".", 1)[1]
    return slider_key


def sweepable(sc: physics.Scenario) -> list[str]:
    """The slider keys (controls.PARAMS) of this scenario's system that a sweep can vary in it."""
    allowed = set(physics.numeric_keys(sc))
    return [p.key for p in controls.PARAMS if sc.system in p.systems and scenario_key(p.key, sc.system) in allowed]


def default_range(sc: physics.Scenario, key: str) -> tuple[float, float]:
    """value / RANGE_FACTOR .. value * RANGE_FACTOR around the current value (a tuned k's value), or the
    slider's range at 0."""
    p = controls.BY_KEY[key]
    v = controls.values_of(sc).get(key, 0.0)
    if key == "pendulum.k" and v == 0 and sc.pendulum is not None and isinstance(sc.pendulum.k, str):
        v = float(physics.derived(sc).get("k", 0.0))  # "resonant"/"optimal": the stiffness it tunes to
    if v > 0:
        return v / RANGE_FACTOR, v * RANGE_FACTOR
    if v < 0:
        return v * RANGE_FACTOR, v / RANGE_FACTOR
    return (p.lo, p.hi) if p.hi > p.lo else (0.0, 1.0)


def point_label(table: physics.SweepTable, i: int) -> str:
    row = table.rows[i]
    where = ", ".join(f"{k.split('.', 1)[1]} = {row[k]:.4g}" for k in table.keys)
    value = row[table.metric]
    shown = row["error"].split(":", 1)[0] if row["error"] else controls.fmt(value)
    return f"#{i}: {where} -> {table.metric} {shown}"


def ranked(table: physics.SweepTable) -> list[int]:
    """Row indices, finite metric values first in increasing order, then the rest in grid order."""
    def order(i):
        v = table.rows[i][table.metric]
        return (0, v, i) if math.isfinite(v) else (1, 0.0, i)

    return sorted(range(len(table.rows)), key=order)


def figure(table: physics.SweepTable):
    """A plotly figure: the curve (one key) or the heat map (two keys) of the table's metric."""
    import plotly.graph_objects as go

    unit = physics.METRICS[table.metric].unit
    z = [[v if math.isfinite(v) else None for v in row] for row in table.grid().reshape(len(table.axes[0]), -1)]
    if len(table.keys) == 1:
        fig = go.Figure(go.Scatter(x=list(table.axes[0]), y=[r[0] for r in z], mode="lines+markers",
                                   hovertemplate=f"{table.keys[0]} = %{{x:.4g}}<br>{table.metric} = %{{y:.4g}}"))
        fig.update_xaxes(title_text=table.keys[0], type="log" if table.spacing[0] == "log" else "linear")
        fig.update_yaxes(title_text=f"{table.metric} ({unit})")
    else:
        fig = go.Figure(go.Heatmap(x=list(table.axes[1]), y=list(table.axes[0]), z=z, colorscale="Viridis",
                                   colorbar={"title": {"text": unit}}))
        fig.update_xaxes(title_text=table.keys[1], type="log" if table.spacing[1] == "log" else "linear")
        fig.update_yaxes(title_text=table.keys[0], type="log" if table.spacing[0] == "log" else "linear")
    fig.update_layout(title={"text": table.metric, "font": {"size": 13}}, margin={"l": 50, "r": 10, "t": 30, "b": 40})
    return fig


BOARD_MAX = 400  # cells drawn in the scene; a larger sweep is listed in the dropdown only
BOARD_SIZE = 2.0  # scene units the board spans (the body spans 1.5)
BOARD_AT = (2.2, -1.0, -1.38)  # its corner: beside the body, just above the floor grid
RAMP = ((68, 1, 84), (33, 145, 140), (253, 231, 37))  # viridis' ends and middle: small values dark


def ramp(x: float) -> tuple[int, int, int]:
    """Colour of a value scaled to [0, 1] (viridis-like, by linear steps between three stops)."""
    x = min(max(x, 0.0), 1.0) * (len(RAMP) - 1)
    i = min(int(x), len(RAMP) - 2)
    f = x - i
    return tuple(int(round(a + f * (b - a))) for a, b in zip(RAMP[i], RAMP[i + 1], strict=True))


def board_cells(table: physics.SweepTable) -> list[tuple[int, tuple[float, float, float], tuple, float]]:
    """(row, cell centre, colour, height) of every point: the first key along y, the second along x;
    finite metric values scaled to [0, 1] give colour and height, failed points are grey and flat."""
    n1 = len(table.axes[0])
    n2 = len(table.axes[1]) if len(table.keys) > 1 else 1
    cell = BOARD_SIZE / max(n1, n2)
    values = table.column(table.metric)
    finite = values[np.isfinite(values)]
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    out = []
    for i, v in enumerate(values):
        a, b = divmod(i, n2)
        x = (v - lo) / (hi - lo) if np.isfinite(v) and hi > lo else 0.5
        color = ramp(x) if np.isfinite(v) else (150, 150, 150)
        height = 0.05 + 0.3 * cell * x if np.isfinite(v) else 0.02
        centre = (BOARD_AT[0] + (b + 0.5) * cell, BOARD_AT[1] + (a + 0.5) * cell, BOARD_AT[2] + height / 2)
        out.append((i, centre, color, height))
    return out


class SweepBoard:
    """The sweep's points as clickable cells in the scene; ``on_pick(row)`` runs when one is clicked."""

    def __init__(self, scene, on_pick: Callable[[int], None], root: str = "/sweep_board"):
        self.scene, self.on_pick, self.root = scene, on_pick, root
        self.handles: list = []

    def clear(self) -> None:
        for h in reversed(self.handles):
            try:
                h.remove()
            except Exception:  # noqa: BLE001 - already gone with the client
                pass
        self.handles = []

    def show(self, table: physics.SweepTable) -> bool:
        """Draw ``table`` (False, and nothing drawn, beyond BOARD_MAX points)."""
        self.clear()
        if len(table.rows) > BOARD_MAX:
            return False
        cells = board_cells(table)
        cell = BOARD_SIZE / max(len(a) for a in table.axes)
        self.handles.append(self.scene.add_label(
            f"{self.root}/title", f"sweep: {table.metric} (click a cell to load it)",
            position=(BOARD_AT[0], BOARD_AT[1] - 0.15, BOARD_AT[2]), font_screen_scale=0.7))
        for i, centre, color, height in cells:
            box = self.scene.add_box(f"{self.root}/cell{i}", color=color, dimensions=(0.9 * cell, 0.9 * cell, height),
                                     position=centre, cast_shadow=False, receive_shadow=False)
            box.on_click(lambda _event, i=i: self.on_pick(i))
            self.handles.append(box)
        return True


class SweepPanel:
    """Widgets added to the current gui context. ``get_scenario()`` is the scene's scenario when Run is
    pressed; ``load_scenario(sc)`` is called (from the GUI callback thread) when a point is loaded.
    ``executor``/``workers`` go to physics.sweep (local processes on all cores by default)."""

    def __init__(self, gui, get_scenario: Callable[[], physics.Scenario],
                 load_scenario: Callable[[physics.Scenario], None], *, workers: int | None = None,
                 executor: str = "processes", scene=None):
        self.get_scenario, self.load_scenario = get_scenario, load_scenario
        self.board = SweepBoard(scene, self.load_point) if scene is not None else None
        self.workers, self.executor = workers, executor
        self.table: physics.SweepTable | None = None
        self.thread: threading.Thread | None = None
        self.stop = threading.Event()
        self._points: dict[str, int] = {}
        sc = get_scenario()
        self.system = sc.system
        keys = sweepable(sc) or [NONE]
        self.status = gui.add_markdown("Vary one or two parameters; each point is a full run.")
        self.key1 = gui.add_dropdown("parameter", keys, initial_value=keys[0],
                                     hint="the slider to vary (along the curve, or down the heat map)")
        self.lo1 = gui.add_number("from", 0.0)
        self.hi1 = gui.add_number("to", 1.0)
        self.n1 = gui.add_number("points", DEFAULT_POINTS, min=1, max=MAX_POINTS, step=1)
        self.log1 = gui.add_checkbox("log spacing", False, hint="geometric spacing (both ends must be > 0)")
        self.key2 = gui.add_dropdown("second parameter", [NONE, *keys], initial_value=NONE,
                                     hint="a second slider makes a heat map (across)")
        self.lo2 = gui.add_number("from (2nd)", 0.0)
        self.hi2 = gui.add_number("to (2nd)", 1.0)
        self.n2 = gui.add_number("points (2nd)", DEFAULT_POINTS, min=1, max=MAX_POINTS, step=1)
        self.log2 = gui.add_checkbox("log spacing (2nd)", False)
        self.metric = gui.add_dropdown("metric", list(physics.METRICS), initial_value="decay_time",
                                       hint="; ".join(f"{m.name}: {m.meaning} ({m.unit})"
                                                      for m in physics.METRICS.values()))
        self.run_btn = gui.add_button("Run sweep")
        self.stop_btn = gui.add_button("Stop sweep", disabled=True)
        self.bar = gui.add_progress_bar(0.0)
        self.plot = gui.add_plotly(self._empty_figure(), aspect=1.3)
        self.point = gui.add_dropdown("point", [NO_POINTS], initial_value=NO_POINTS,
                                      hint="computed points, best (smallest metric) first")
        self.load_btn = gui.add_button("Load this point", disabled=True)
        self.key1.on_update(lambda _: self._reset_range(1))
        self.key2.on_update(lambda _: self._reset_range(2))
        self.run_btn.on_click(lambda _: self.start())
        self.stop_btn.on_click(lambda _: self.stop.set())
        self.load_btn.on_click(lambda _: self.load_selected())
        self._reset_range(1)
        self._reset_range(2)

    # ---- widgets --------------------------------------------------------------------------------
    @staticmethod
    def _empty_figure():
        import plotly.graph_objects as go

        fig = go.Figure()
        fig.update_layout(margin={"l": 10, "r": 10, "t": 10, "b": 10})
        return fig

    def _reset_range(self, which: int) -> None:
        key = (self.key1 if which == 1 else self.key2).value
        lo, hi, log = (self.lo1, self.hi1, self.log1) if which == 1 else (self.lo2, self.hi2, self.log2)
        visible = key != NONE
        for h in ((lo, hi, log, self.n2) if which == 2 else ()):
            h.visible = visible
        if key not in controls.BY_KEY:
            return
        try:
            a, b = default_range(self.get_scenario(), key)
        except Exception:  # noqa: BLE001 - a scenario being swapped out: keep the old range
            return
        lo.value, hi.value = float(f"{a:.4g}"), float(f"{b:.4g}")

    def refresh(self) -> None:
        """Rebuild the parameter lists for the scene's current system (call after a system change)."""
        sc = self.get_scenario()
        self.system = sc.system
        keys = sweepable(sc) or [NONE]
        self.key1.options = keys
        self.key2.options = [NONE, *keys]
        if self.key1.value not in keys:
            self.key1.value = keys[0]
        if self.key2.value not in self.key2.options:
            self.key2.value = NONE

    def _say(self, text: str) -> None:
        self.status.content = text

    # ---- running --------------------------------------------------------------------------------
    def request(self) -> tuple[physics.Scenario, dict, str]:
        """(scenario, vary, metric) from the widgets; raises ScenarioError on bad input."""
        sc = self.get_scenario()
        if sc.system != self.system:
            self.refresh()
            raise physics.ScenarioError("parameter", self.key1.value, f"the scene is now a {sc.system}: the lists "
                                        "were updated; pick again")
        vary = {}
        for key, lo, hi, n, log in ((self.key1.value, self.lo1, self.hi1, self.n1, self.log1),
                                    (self.key2.value, self.lo2, self.hi2, self.n2, self.log2)):
            if key == NONE:
                continue
            if key not in controls.BY_KEY:
                raise physics.ScenarioError("parameter", key, "is not a slider of the explorer")
            count = int(n.value)
            if not 1 <= count <= MAX_POINTS:
                raise physics.ScenarioError(f"points of {key}", n.value, f"must be from 1 to {MAX_POINTS}")
            spec = ("log", lo.value, hi.value, count) if log.value else (lo.value, hi.value, count)
            physics.axis_values(spec, key)  # a bad range is reported before anything starts
            vary[scenario_key(key, sc.system)] = spec
        if len(vary) < (2 if self.key2.value != NONE else 1):
            raise physics.ScenarioError("second parameter", self.key2.value, "must differ from the first")
        return sc, vary, self.metric.value

    def start(self) -> threading.Thread | None:
        """Start a sweep in a daemon thread (ignored while one runs); returns the thread."""
        if self.thread is not None and self.thread.is_alive():
            self._say("A sweep is running; **Stop sweep** ends it.")
            return None
        try:
            sc, vary, metric = self.request()
            n = math.prod(spec[-1] for spec in vary.values())
        except Exception as exc:  # noqa: BLE001 - shown, never raised into viser
            self._say(f"**Cannot start:** {exc}")
            return None
        self.stop.clear()
        self.bar.value = 0.0
        self.run_btn.disabled, self.stop_btn.disabled = True, False
        self._say(f"Running {n} simulations on local workers...")
        self.thread = threading.Thread(target=self._work, args=(sc, vary, metric), name="sweep", daemon=True)
        self.thread.start()
        return self.thread

    def _progress(self, done: int, total: int) -> None:
        self.bar.value = 100.0 * done / total if total else 100.0

    def _work(self, sc: physics.Scenario, vary: dict, metric: str) -> None:
        try:
            table = physics.sweep(sc, vary, metric, workers=self.workers, executor=self.executor,
                                  progress=self._progress, stop=self.stop)
            self.show(table)
        except Exception as exc:  # noqa: BLE001 - the panel reports, the server goes on
            self._say(f"**Sweep failed:** {type(exc).__name__}: {exc}")
        finally:
            self.run_btn.disabled, self.stop_btn.disabled = False, True

    def show(self, table: physics.SweepTable) -> None:
        """Chart ``table`` and list its points for loading."""
        self.table = table
        self.plot.figure = figure(table)
        order = ranked(table)
        self._points = {point_label(table, i): i for i in order}
        labels = list(self._points)
        self.point.options = labels
        self.point.value = labels[0]
        self.load_btn.disabled = False
        failed = sum(1 for r in table.rows if r["error"])
        best = table.rows[order[0]]
        note = (f"{len(table.rows)} points in {table.wall_s:.1f} s" + (" (stopped)" if table.stopped else "")
                + (f", {failed} failed" if failed else "") + f". Smallest {table.metric}: "
                + (controls.fmt(best[table.metric]) if not best["error"] else "none"))
        if self.board is not None:
            drawn = self.board.show(table)
            note += (" Click a cell of the board beside the body to load its point." if drawn else
                     f" (Over {BOARD_MAX} points: pick them from the list.)")
        self._say(note)

    def load_selected(self) -> physics.Scenario | None:
        """Hand the selected point's scenario to ``load_scenario``; returns it (None if impossible)."""
        if self.table is None or self.point.value not in self._points:
            self._say("Run a sweep first, then pick a point.")
            return None
        return self.load_point(self._points[self.point.value])

    def load_point(self, i: int) -> physics.Scenario | None:
        """Hand row ``i``'s scenario to ``load_scenario`` (a dropdown choice or a clicked cell)."""
        if self.table is None or not 0 <= i < len(self.table.rows):
            return None
        try:
            sc = self.table.scenario(i)
            self.load_scenario(sc)
        except Exception as exc:  # noqa: BLE001
            self._say(f"**Cannot load point #{i}:** {exc}")
            return None
        self._say(f"Loaded point #{i}: " + ", ".join(f"{k} = {self.table.rows[i][k]:.6g}" for k in self.table.keys))
        return sc
