"""The Design panel: pick up to three sliders, their ranges and an objective; physics.design finds the best point
within them in the background (progress and each run's objective shown as they come), then offers the optimum with
one click, or beside the current scene or the papers' tuning in compare mode.

The controls sit in the panel's folder; the result (the optimum in words, the chart of the objective run by run,
the buttons) goes to a movable window of its own (results_window.py). Default ranges are the sweep's: valid scenes
at every point (sweep_ranges.py). When the scene changes other than by taking the optimum, the result is marked
stale. Nothing here raises into viser: a failed design or bad input becomes a message in the panel.
"""

from __future__ import annotations

import contextlib
import math
import threading
from collections.abc import Callable

import physics

from ..engine import controls
from ..engine.compare import SLIDERS
from . import design_view, results_window
from .background import BackgroundStudy
from .slider_choice import NONE, key_of, offer, options, slider_map
from .stale import same_scene
from .sweep_ranges import reset_range, scenario_key

SLOTS = 3  # sliders a design varies from the explorer (physics.design takes four)
DEFAULT_RUNS = 120
LIVE_EVERY = 5  # runs between redraws of the live chart and status line
MIN_RUNS, MAX_RUNS = 20, 400
BESIDE_SCENE = "this scene"
NO_RESULT = "(run a design first)"
READY = "**Run design** runs it; its progress and any refusal show here."
STALE = "**Stale:** the scene has changed since this design; its optimum is for the earlier scene. Run it again " \
        "for the current one."
OBJECTIVE_HINT = "; ".join(f"{name}: {design_view.GOAL_WORDS[goal]} {physics.METRICS[name].meaning} "
                           f"({physics.METRICS[name].unit})" for name, goal in physics.OBJECTIVES.items())


def runs_of(value) -> int | None:
    """A runs box's value as a count from MIN_RUNS to MAX_RUNS, else None (a raw client can send anything)."""
    try:
        n = int(value)
    except (TypeError, ValueError, OverflowError):
        return None
    return n if MIN_RUNS <= n <= MAX_RUNS and n == value and not isinstance(value, bool) else None


class DesignPanel(BackgroundStudy):
    """Widgets added to the current gui context. ``get_scenario()`` is the scene's scenario when Run is pressed;
    ``load_scenario(sc)`` loads a scene (the optimum, or the papers' tuning to compare beside); ``compare(spec)``
    turns compare mode on (app.engine.compare.parse's spec). ``executor``/``workers`` go to physics.design."""

    def __init__(self, gui, get_scenario: Callable[[], physics.Scenario],
                 load_scenario: Callable[[physics.Scenario], None], *, compare: Callable[[object], None] | None = None,
                 workers: int | None = None, executor: str = "processes"):
        super().__init__()
        self.get_scenario, self.load_scenario, self.compare = get_scenario, load_scenario, compare
        self.workers, self.executor = workers, executor
        self.result: physics.DesignResult | None = None
        self.sliders: dict[str, str] = {}
        self.stale = False
        self._live: list = []  # the running design's runs so far, in the order they finished (the live chart)
        self._live_lock = threading.Lock()
        self._running = "decay_time"  # the running design's objective
        sc = get_scenario()
        self.system = sc.system
        gui.add_markdown("Pick up to three sliders, their ranges and an objective: the design finds "
                         "the best point within them.")
        self.slots = []
        names = ("parameter", "second parameter", "third parameter")
        for i, name in enumerate(names):
            offered = options(sc, optional=i > 0)
            key = gui.add_dropdown(name, offered, initial_value=offered[0],
                                   hint="a slider the design varies" + ("" if i == 0 else " (none: fewer)"))
            suffix = "" if i == 0 else f" ({i + 1}{'nd' if i == 1 else 'rd'})"
            lo = gui.add_number("from" + suffix, 0.0, step=0.01)
            hi = gui.add_number("to" + suffix, 1.0, step=0.01)
            self.slots.append((key, lo, hi))
            key.on_update(lambda _, i=i: self._reset_range(i))
        self.objective = gui.add_dropdown("objective", list(physics.OBJECTIVES), initial_value="decay_time",
                                          hint=OBJECTIVE_HINT)
        self.runs = gui.add_number("runs at most", DEFAULT_RUNS, min=MIN_RUNS, max=MAX_RUNS, step=1,
                                   hint="the design's runs, the full model's check of the optimum included")
        self.run_btn = gui.add_button("Run design")
        self.stop_btn = gui.add_button("Stop design", disabled=True)
        self.bar = gui.add_progress_bar(0.0)
        self.status = gui.add_markdown(READY)  # under Run and Stop, in sight of them at 1024x768 (sweep_panel.py)
        tab = results_window.results_tab(gui, "Design")
        with tab if tab is not None else contextlib.nullcontext():
            self.result_md = gui.add_markdown("Run a design (**Run design**, in the panel's Design folder): its "
                                             "optimum and its runs appear here.")
            self.plot = gui.add_plotly(design_view.figure(None), aspect=0.625, config={"displayModeBar": False})
            self.take_btn = gui.add_button("Take the optimum", disabled=True,
                                           hint="load the scene with the optimum's values")
            self.beside = gui.add_dropdown("compare the optimum beside", [NO_RESULT], initial_value=NO_RESULT,
                                           hint="this scene, or the papers' tuning of this system, as the first run")
            self.compare_btn = gui.add_button("Compare the optimum", disabled=True)
        self.runs.on_update(lambda _: self._take_runs())
        self.run_btn.on_click(lambda _: self.start())
        self.stop_btn.on_click(lambda _: self.stop.set())
        self.take_btn.on_click(lambda _: self.take())
        self.compare_btn.on_click(lambda _: self.compare_optimum())
        self._runs = DEFAULT_RUNS
        for i in range(SLOTS):
            self._reset_range(i)

    # ---- widgets ----------------------------------------------------------------------------------------
    def _take_runs(self) -> None:
        n = runs_of(self.runs.value)
        if n is None:
            self._say(f"**runs at most:** {str(self.runs.value)[:40]!r} refused; a whole number from {MIN_RUNS} to "
                      f"{MAX_RUNS}; {self._runs} kept")
            self.runs.value = self._runs
        else:
            self._runs = n

    def _reset_range(self, i: int) -> None:
        key, lo, hi = self.slots[i]
        for h in (lo, hi):
            h.visible = key.value != NONE
        reset_range(lo, hi, self.get_scenario, key_of(key.value, self.system), 8)

    def refresh(self) -> None:
        """Rebuild the slider lists for the scene's current system (call after a system change)."""
        sc = self.get_scenario()
        self.system = sc.system
        for i, (key, _lo, _hi) in enumerate(self.slots):
            offer(key, options(sc, optional=i > 0))
        self.scene_changed()

    def scene_changed(self) -> None:
        """Mark the result stale when the scene differs from the design's apart from its keys."""
        if self.result is None:
            return
        try:  # called from the session's loop: never raise into it
            stale = not same_scene(self.result.base, self.get_scenario(), ignore=self.result.keys)
            if stale != self.stale:
                self.stale = stale
                self._show_result()
        except Exception:  # noqa: BLE001 - a scenario being swapped out: judged again at the next change
            pass

    # ---- running ------------------------------------------------------------------------------------------
    def request(self) -> tuple[physics.Scenario, dict, str, int]:
        """(scenario, vary, objective, runs) from the widgets; raises ScenarioError on bad input."""
        sc = self.get_scenario()
        if sc.system != self.system:
            self.refresh()
            raise physics.ScenarioError("parameter", self.slots[0][0].value, f"the scene is now a {sc.system}: the "
                                        "lists were updated; pick again")
        vary = {}
        for key, lo, hi in self.slots:
            if key.value == NONE:
                continue
            slider = key_of(key.value, sc.system)
            if slider is None:
                raise physics.ScenarioError("parameter", str(key.value)[:40], "must be one of "
                                            + ", ".join(options(sc, optional=False)))
            dotted = scenario_key(slider, sc.system)
            if dotted in vary:
                raise physics.ScenarioError("parameter", key.value, "is chosen twice: pick different sliders")
            a, b = float(lo.value), float(hi.value)
            if not (math.isfinite(a) and math.isfinite(b) and a < b):  # said before anything starts
                raise physics.ScenarioError(f"from/to of {controls.BY_KEY[slider].label}", f"{a:g} .. {b:g}",
                                            "must be finite with from < to")
            vary[dotted] = (a, b)
        runs = runs_of(self.runs.value)
        if runs is None:
            raise physics.ScenarioError("runs at most", self.runs.value, f"must be from {MIN_RUNS} to {MAX_RUNS}")
        if self.objective.value not in physics.OBJECTIVES:  # a raw client can send any text
            raise physics.ScenarioError("objective", str(self.objective.value)[:40], "must be one of "
                                        + ", ".join(physics.OBJECTIVES))
        return sc, vary, self.objective.value, runs

    NOUN = "design"

    def has_result(self) -> bool:
        return self.result is not None

    def prepare(self) -> tuple[tuple, str]:
        sc, vary, objective, runs = self.request()
        sliders = slider_map(sc.system)
        ranges = "; ".join(f"{controls.BY_KEY[sliders[k]].label} from {lo:.6g} to {hi:.6g}" for k, (lo, hi) in
                           vary.items())
        self._live, self._running = [], objective
        goal = design_view.GOAL_WORDS[physics.OBJECTIVES[objective]]
        return (sc, vary, objective, runs), (f"Designing for the {goal} {objective}: {ranges}, at most {runs} runs "
                                             "on local workers...")

    def _progress(self, done: int, budget: int, e) -> None:
        """Called once per run from the design's threads: the bar, and every LIVE_EVERY runs the status line and
        the chart of the runs so far (each chart is sent whole to the browser, so not on every run)."""
        with self._live_lock:
            self._live.append(e)
            path = list(self._live)
        self.bar.value = min(100.0 * done / budget, 100.0) if budget else 100.0
        if done == 1 or done % LIVE_EVERY == 0:
            value = f"{e.objective:.4g}" if math.isfinite(e.objective) else "failed"
            self._say(f"Run {done} of at most {budget} ({e.phase}): {value}")
            objective = self._running
            self.plot.figure = design_view.path_figure(path, physics.OBJECTIVES[objective], objective,
                                                       physics.METRICS[objective].unit)

    def work(self, sc: physics.Scenario, vary: dict, objective: str, runs: int) -> None:
        try:
            result = physics.design(sc, vary, objective, budget=runs, workers=self.workers, executor=self.executor,
                                    progress=self._progress, stop=self.stop)
        except physics.DesignStopped:
            results_window.say(self.status, self.result_md, "Stopped before the first run ended: there is no "
                               "optimum to show. **Run design** starts again.", self.has_result())
            return
        self.show(result)

    def show(self, result: physics.DesignResult) -> None:
        """Show ``result`` in the Design window and offer the optimum."""
        self.result, self.stale = result, False
        self.sliders = slider_map(result.base.system)
        self.bar.value = 100.0
        self._show_result()
        self.beside.options = [BESIDE_SCENE, *result.references]
        self.beside.value = BESIDE_SCENE
        self.take_btn.disabled = False
        self.compare_btn.disabled = self.compare is None
        self._say(f"Done: {result.evaluations} runs in {result.wall_s:.1f} s" + (" (stopped)" if result.stopped else "")
                  + ". The optimum is in the Design window: **Take the optimum** loads it.")
        self.scene_changed()  # the scene may have changed while the design ran

    def _show_result(self) -> None:
        self.plot.figure = design_view.figure(self.result, stale=self.stale)
        self.result_md.content = (STALE + "  \n" if self.stale else "") + design_view.summary(self.result,
                                                                                                self.sliders)

    # ---- the optimum ----------------------------------------------------------------------------------------
    def take(self) -> physics.Scenario | None:
        """Load the scene with the optimum's values; returns it (None if impossible)."""
        if self.result is None:
            self._say("Run a design first.")
            return None
        try:
            sc = self.result.scenario()
            self.load_scenario(sc)
        except Exception as exc:  # noqa: BLE001
            self._say(f"**Cannot take the optimum:** {exc}")
            return None
        self._say("Took the optimum: " + ", ".join(design_view.named(self.sliders[k], v)
                                                   for k, v in self.result.best.items()))
        return sc

    def compare_optimum(self) -> None:
        """Compare mode with the optimum as the second run, beside this scene or beside the papers' tuning (loaded
        first, as the first run)."""
        if self.result is None or self.compare is None:
            self._say("Run a design first.")
            return
        pairs = tuple((self.sliders[k], v) for k, v in self.result.best.items())
        beside = self.beside.value
        try:
            if beside != BESIDE_SCENE:
                if beside not in self.result.references:
                    raise physics.ScenarioError("compare the optimum beside", beside, "is not offered for this design")
                values = self.result.references[beside][0]
                self.load_scenario(self.result.base.with_values(**values))
            self.compare((SLIDERS, pairs))
        except Exception as exc:  # noqa: BLE001
            self._say(f"**Cannot compare:** {exc}")
            return
        self._say(f"Comparing the optimum (run 2) beside {beside} (run 1).")
