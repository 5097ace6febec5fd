"""The sweep panel: pick one or two sliders, their ranges and a metric; the sweep runs in the background
on local worker processes (physics.sweep), with a progress bar, then shows the curve or heat map.

The controls sit in the panel's folder; the result (the best point, the chart, the points best first with
"Load this point") goes to a tab of the movable results window (results_window.py), where the chart has
room. Default ranges are valid scenes at every point (sweep_ranges.py); "best" follows the metric's goal
and the colours cope with outliers (sweep_view.py); when the scene changes other than by loading one of
the sweep's points, the result is marked stale (``scene_changed``). viser's plotly chart reports no
clicks, so the points can also be drawn as clickable cells in the 3-D scene (sweep_board.py, opt-in).
Nothing here raises into viser: a failed sweep or an invalid point becomes a message in the panel.
"""

from __future__ import annotations

import contextlib
import itertools
import math
from collections.abc import Callable

import physics

from . import results_window, sweep_view
from .background import BackgroundStudy
from .slider_choice import NONE, key_of, offer, options
from .stale import same_scene
from .sweep_board import BOARD_MAX, SweepBoard
from .sweep_ranges import reset_range, scenario_key

NO_POINTS = "(run a sweep first)"
DEFAULT_POINTS = 8  # per parameter: 8 x 8 = 64 runs is a minute or so for the presets on two cores
MAX_POINTS = 60  # per parameter, so a misclick cannot queue thousands of runs
READY = "**Run sweep** runs every point; its progress and any refusal show here."
STALE = "**Stale:** the scene has changed since this sweep; its points are those of the earlier scene. " \
        "Run the sweep again for the current one."


def count_of(value) -> int | None:
    """A points box's value as a count: a whole number from 1 to MAX_POINTS, else None. The box's bounds hold
    only in the browser; a raw client sent 1e9 and the next range reset sized arrays by it (issue 24: 3.5 GB)."""
    try:
        n = int(value)
    except (TypeError, ValueError, OverflowError):
        return None
    return n if 1 <= n <= MAX_POINTS and n == value and not isinstance(value, bool) else None


class SweepPanel(BackgroundStudy):
    """Widgets added to the current gui context. ``get_scenario()`` is the scene's scenario when Run is
    pressed; ``load_scenario(sc)`` is called (from the GUI callback thread) when a point is loaded.
    ``executor``/``workers`` go to physics.sweep (local processes on all cores by default); ``scene``
    lets the user draw the points as clickable cells in the 3-D scene."""

    def __init__(self, gui, get_scenario: Callable[[], physics.Scenario],
                 load_scenario: Callable[[physics.Scenario], None], *, workers: int | None = None,
                 executor: str = "processes", scene=None):
        super().__init__()
        self.get_scenario, self.load_scenario = get_scenario, load_scenario
        self.board = SweepBoard(scene, self.load_point) if scene is not None else None
        self.workers, self.executor = workers, executor
        self.table: physics.SweepTable | None = None
        self.stale = False
        self._points: dict[str, int] = {}
        sc = get_scenario()
        self.system = sc.system
        first, second = options(sc, optional=False), options(sc, optional=True)
        gui.add_markdown("Vary one or two parameters; each point is a full run.")
        self.key1 = gui.add_dropdown("parameter", first, initial_value=first[0],
                                     hint="the slider to vary (along the curve, or down the heat map)")
        self.lo1 = gui.add_number("from", 0.0, step=0.01)
        self.hi1 = gui.add_number("to", 1.0, step=0.01)
        self.n1 = gui.add_number("points", DEFAULT_POINTS, min=1, max=MAX_POINTS, step=1)
        self.log1 = gui.add_checkbox("log spacing", False, hint="geometric spacing (both ends must be > 0)")
        self.key2 = gui.add_dropdown("second parameter", second, initial_value=NONE,
                                     hint="a second slider makes a heat map (across)")
        self.lo2 = gui.add_number("from (2nd)", 0.0, step=0.01)
        self.hi2 = gui.add_number("to (2nd)", 1.0, step=0.01)
        self.n2 = gui.add_number("points (2nd)", DEFAULT_POINTS, min=1, max=MAX_POINTS, step=1)
        self.log2 = gui.add_checkbox("log spacing (2nd)", False)
        self.metric = gui.add_dropdown("metric", list(physics.METRICS), initial_value="decay_time",
                                       hint="; ".join(f"{m.name}: {m.meaning} ({m.unit})"
                                                      for m in physics.METRICS.values()))
        self.run_btn = gui.add_button("Run sweep")
        self.stop_btn = gui.add_button("Stop sweep", disabled=True)
        self.bar = gui.add_progress_bar(0.0)
        # under Run and Stop, not at the folder's top: at 1024x768 the top is a scroll away from the buttons,
        # and a refusal there looked like a click that got no answer
        self.status = gui.add_markdown(READY)
        self.board_box = gui.add_checkbox("cells in the 3-D scene", False, visible=scene is not None,
                                          hint="also draw the points on the floor in front of the body; "
                                          "clicking a cell loads its point")
        tab = results_window.results_tab(gui, "Sweep")
        with tab if tab is not None else contextlib.nullcontext():
            self.result_md = gui.add_markdown("Run a sweep (**Run sweep**, in the panel's Sweep folder): its best "
                                             "point, chart and points appear here.")
            # viser's browser side sizes a plotly chart as height = aspect x width (measured: 0.625 gives
            # 520 x 326 px), so a wide chart needs an aspect below 1
            blank = results_window.blank_chart("the metric over the points swept, once they are run")
            self.plot = gui.add_plotly(blank, aspect=0.625, config={"displayModeBar": False})
            self.point = gui.add_dropdown("point", [NO_POINTS], initial_value=NO_POINTS,
                                          hint="computed points: the best (by the rule above) first, then the "
                                          "others, then the failed ones")
            self.load_btn = gui.add_button("Load this point", disabled=True)
        self._counts = {1: DEFAULT_POINTS, 2: DEFAULT_POINTS}  # the points each box last took
        self.n1.on_update(lambda _: self._take_count(1))
        self.n2.on_update(lambda _: self._take_count(2))
        self.key1.on_update(lambda _: self._reset_range(1))
        self.key2.on_update(lambda _: self._reset_range(2))
        self.run_btn.on_click(lambda _: self.start())
        self.stop_btn.on_click(lambda _: self.stop.set())
        self.load_btn.on_click(lambda _: self.load_selected())
        self.board_box.on_update(lambda _: self._draw_board())
        self._reset_range(1)
        self._reset_range(2)

    # ---- widgets --------------------------------------------------------------------------------
    def _take_count(self, which: int) -> None:
        """Keep a points box's count if it is one (``count_of``); otherwise say so and show the count that runs."""
        box = self.n1 if which == 1 else self.n2
        n = count_of(box.value)
        if n is None:
            self._say(f"**{box.label}:** {str(box.value)[:40]!r} refused; a whole number from 1 to {MAX_POINTS}; "
                      f"{self._counts[which]} kept")
            box.value = self._counts[which]
        else:
            self._counts[which] = n

    def _reset_range(self, which: int) -> None:
        text = (self.key1 if which == 1 else self.key2).value
        lo, hi, log, n = ((self.lo1, self.hi1, self.log1, self.n1) if which == 1 else
                          (self.lo2, self.hi2, self.log2, self.n2))
        for h in ((lo, hi, log, n) if which == 2 else ()):
            h.visible = text != NONE
        reset_range(lo, hi, self.get_scenario, key_of(text, self.system), count_of(n.value) or self._counts[which])

    def refresh(self) -> None:
        """Rebuild the parameter lists for the scene's current system (call after a system change)."""
        sc = self.get_scenario()
        self.system = sc.system
        offer(self.key1, options(sc, optional=False))
        offer(self.key2, options(sc, optional=True))
        self.scene_changed()

    def scene_changed(self) -> None:
        """Mark the result stale when the scene differs from the sweep's, apart from the swept keys
        (loading one of its points keeps it current); the session calls this on every scene change."""
        if self.table is None:
            return
        try:  # called from the session's loop: never raise into it
            stale = not same_scene(self.table.base, self.get_scenario(), ignore=self.table.keys)
            if stale != self.stale:
                self.stale = stale
                self.plot.figure = sweep_view.figure(self.table, stale=stale)
                self.result_md.content = (STALE + "  \n" if stale else "") + sweep_view.summary(self.table)
                if stale and self.board is not None:
                    self.board.clear()
        except Exception:  # noqa: BLE001 - a scenario being swapped out: judged again at the next change
            pass

    # ---- running --------------------------------------------------------------------------------
    def request(self) -> tuple[physics.Scenario, dict, str]:
        """(scenario, vary, metric) from the widgets; raises ScenarioError on bad input."""
        sc = self.get_scenario()
        if sc.system != self.system:
            self.refresh()
            raise physics.ScenarioError("parameter", self.key1.value, f"the scene is now a {sc.system}: the lists "
                                        "were updated; pick again")
        vary, ends = {}, {}
        for text, lo, hi, n, log in ((self.key1.value, self.lo1, self.hi1, self.n1, self.log1),
                                     (self.key2.value, self.lo2, self.hi2, self.n2, self.log2)):
            if text == NONE:
                continue
            key = key_of(text, sc.system)
            if key is None:
                raise physics.ScenarioError("parameter", str(text)[:40], "must be one of "
                                            + ", ".join(options(sc, optional=False)))
            count = count_of(n.value)
            if count is None:
                raise physics.ScenarioError(f"points of {text}", n.value, f"must be from 1 to {MAX_POINTS}")
            a, b = float(lo.value), float(hi.value)
            spec = ("log", a, b, count) if log.value else (a, b, count)
            values, _ = physics.axis_values(spec, text)  # a bad range is reported before anything starts
            vary[scenario_key(key, sc.system)] = spec
            ends[scenario_key(key, sc.system)] = (values[0], values[-1])  # one point: "to" is not run
        if len(vary) < (2 if self.key2.value != NONE else 1):
            raise physics.ScenarioError("second parameter", self.key2.value, "must differ from the first")
        for corner in itertools.product(*([(k, v) for v in e] for k, e in ends.items())):
            physics.point_scenario(sc, dict(corner))  # an end no scene can take is refused here, as the sweep builds it
        return sc, vary, self.metric.value

    NOUN = "sweep"

    def has_result(self) -> bool:
        return self.table is not None

    def prepare(self) -> tuple[tuple, str]:
        sc, vary, metric = self.request()
        n = math.prod(spec[-1] for spec in vary.values())
        ranges = "; ".join(f"{k.split('.', 1)[1]} from {s[-3]:.6g} to {s[-2]:.6g} ({s[-1]} points"
                           + (", log" if len(s) == 4 else "") + ")" for k, s in vary.items())
        return (sc, vary, metric), f"Running {n} simulations on local workers: {ranges}..."

    def _progress(self, done: int, total: int) -> None:
        self.bar.value = 100.0 * done / total if total else 100.0

    def work(self, sc: physics.Scenario, vary: dict, metric: str) -> None:
        self.show(physics.sweep(sc, vary, metric, workers=self.workers, executor=self.executor,
                                progress=self._progress, stop=self.stop))

    def show(self, table: physics.SweepTable) -> None:
        """Chart ``table``, say which point is best and why others failed, and list its points for loading."""
        self.table, self.stale = table, False
        self.plot.figure = sweep_view.figure(table)
        order = sweep_view.ranked(table)
        self._points = {sweep_view.point_label(table, i): i for i in order}
        labels = list(self._points)
        self.point.options = labels
        self.point.value = labels[0]
        self.load_btn.disabled = False
        unrun = sum(1 for r in table.rows if table.not_run(r))
        ranges = "; ".join(f"{k.split('.', 1)[1]} from {a[0]:.6g} to {a[-1]:.6g} ({len(a)} points)"
                           for k, a in zip(table.keys, table.axes, strict=True))
        self.result_md.content = sweep_view.summary(table)
        note = (f"{len(table.rows)} points in {table.wall_s:.1f} s"
                + (f" (stopped: {unrun} not run)" if unrun else " (stopped)" if table.stopped else "")
                + (f", {table.failed} failed" if table.failed else "")
                + f": {ranges}. The result is in the Sweep window.")
        if self._draw_board():
            note += " Click a cell on the floor in front of the body to load its point."
        elif self.board_box.value and len(table.rows) > BOARD_MAX:
            note += f" (Over {BOARD_MAX} points: pick them from the list.)"
        self._say(note)
        self.scene_changed()  # the scene may have changed while the sweep ran

    def _draw_board(self) -> bool:
        """Draw the points as cells in the scene when asked to (and not stale); True if drawn."""
        if self.board is None:
            return False
        if not self.board_box.value or self.table is None or self.stale:
            self.board.clear()
            return False
        return self.board.show(self.table)

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
        row = self.table.rows[i]
        if row["error"]:
            self._say(f"**Point #{i} cannot be loaded:** {sweep_view.failure(row)}")
            return None
        try:
            sc = self.table.scenario(i)
            self.load_scenario(sc)
        except Exception as exc:  # noqa: BLE001
            self._say(f"**Cannot load point #{i}:** {exc}")
            return None
        self._say(f"Loaded point #{i}: " + ", ".join(f"{k} = {row[k]:.6g}" for k in self.table.keys))
        return sc
