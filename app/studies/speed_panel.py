"""The "speed vs accuracy" panel: a work-precision sweep of the current scene (physics.work_precision)
in a background thread, with a progress bar, a log-log chart of theta error against wall time (one
trace per method) and a button that switches the scene to the recommended method and setting.

The run controls sit in the panel's folder; the chart, the summary and the button go to a tab of the
movable results window (results_window.py), with the legend below the chart and plotly's toolbar off, so
neither covers the traces. When the scene changes (other than in its run method and step, which applying
the recommendation itself changes) the result is marked stale and cannot be applied (``scene_changed``).
Nothing here raises into viser: a failed sweep becomes a message in the panel.
"""

from __future__ import annotations

import contextlib
import math
import threading
from collections.abc import Callable

import physics

from . import results_window
from .stale import RUN_SETTINGS, same_scene

NOTHING_YET = "Use recommended: (run the sweep first)"
METHOD_NAMES = {"auto": "DOP853 (compiled, adaptive)", "RK4": "RK4 (compiled)", "RK8": "RK8 (compiled)",
                "midpoint": "implicit midpoint (compiled)"}
# the chart's legend: short names, two to a row (the summary above names them in full); with the
# long names the legend took a row each and ran into the axis title in a window ~300 px wide
LEGEND_NAMES = {"auto": "DOP853", "RK4": "RK4", "RK8": "RK8", "midpoint": "implicit midpoint"}
ERROR_FLOOR = 1e-16  # rad: a zero error is drawn here on the log axis
STALE = "**Stale:** the scene has changed since this sweep; run it again for the current scene."
# while a new sweep runs or after it failed, the chart and the button still hold the last sweep's result: the
# status line, which replaces that result's summary, says whose they are
EARLIER = "  \nThe chart and the button below are the earlier sweep's:  \n"


def setting_text(row: physics.WorkPrecisionRow) -> str:
    return f"rtol = {row.setting:.3g}" if row.method == "auto" else f"dt = {row.setting:.4g} s"


def figure(result: physics.WorkPrecision | None, stale: bool = False):
    """A plotly figure: theta error (rad) against wall time (s), log-log, one trace per method, the
    requested tolerance as a dashed line and the recommended point ringed."""
    import plotly.graph_objects as go

    fig = go.Figure()
    if result is not None:
        for method in result.methods():
            rows = sorted((r for r in result.rows if r.method == method), key=lambda r: r.wall_s)
            fig.add_trace(go.Scatter(
                x=[r.wall_s for r in rows], y=[max(r.error, ERROR_FLOOR) for r in rows], mode="lines+markers",
                name=LEGEND_NAMES.get(method, method), text=[setting_text(r) for r in rows],
                hovertemplate="%{text}<br>error %{y:.3g} rad<br>%{x:.3g} s<extra></extra>"))
        if math.isfinite(result.tolerance) and result.tolerance > 0:
            fig.add_hline(y=result.tolerance, line_dash="dash", line_color="gray")
            # placed by hand: add_hline's own label lands at the top on a log axis, where an annotation's
            # y is the exponent, over the traces
            fig.add_annotation(x=1.0, xref="paper", y=math.log10(result.tolerance), yref="y", text="requested",
                               showarrow=False, xanchor="right", yanchor="bottom", font={"size": 10, "color": "gray"})
        best = result.recommended
        if best is not None:
            fig.add_trace(go.Scatter(x=[best.wall_s], y=[max(best.error, ERROR_FLOOR)], mode="markers",
                                     name="recommended", marker={"size": 14, "symbol": "circle-open",
                                                                  "line": {"width": 2}}))
    # one tick a decade, written as powers of ten: short labels that cannot run into each other
    fig.update_xaxes(type="log", title_text="wall time (s)", dtick=1, exponentformat="power")
    fig.update_yaxes(type="log", title_text="theta error (rad)", dtick=2, exponentformat="power")
    # the legend at the figure's foot (container coordinates), below the axis title: placed in the plot's own
    # coordinates it moved with the plot's height and overlapped the title in a small window
    fig.update_layout(margin={"l": 60, "r": 10, "t": 28 if stale else 10, "b": 100},
                      legend={"orientation": "h", "x": 0.0, "xref": "container", "y": 0.0, "yref": "container",
                              "yanchor": "bottom", "entrywidth": 0.5, "entrywidthmode": "fraction",
                              "font": {"size": 10}},
                      title={"text": "STALE: the scene changed since this sweep" if stale else "",
                             "font": {"size": 12}})
    return fig


def summary(result: physics.WorkPrecision) -> str:
    """Markdown: what was measured and what is recommended."""
    head = (f"{len(result.rows)} runs of {result.model} over {result.horizon:.4g} s against DOP853 at "
            f"rtol 1e-13; bar: {result.tolerance:.3g} rad ({result.tolerance_source}).")
    if result.cancelled:
        head = "Stopped early. " + head
    best = result.recommended
    if best is None:
        return head + "  \nNo setting met the bar."
    return (head + f"  \n**Recommended: {METHOD_NAMES.get(best.method, best.method)}, {setting_text(best)}** "
            f"(error {best.error:.3g} rad, {best.wall_s:.3g} s, {best.nfev} evaluations).")


class SpeedPanel:
    """Widgets added to the current gui context. ``get_scenario()`` gives the scene's scenario when the
    sweep starts; ``apply(sc)`` is called (from the GUI callback thread) with the scene's scenario
    switched to the recommended run.method and run.rtol or run.dt. ``sweep`` is physics.work_precision
    (replaceable in tests)."""

    def __init__(self, gui, get_scenario: Callable[[], physics.Scenario],
                 apply: Callable[[physics.Scenario], None], *, sweep=None):
        self.get_scenario, self.apply = get_scenario, apply
        self.sweep = sweep or physics.work_precision
        self.result: physics.WorkPrecision | None = None
        self.swept: physics.Scenario | None = None  # the scene the result was measured on
        self.stale = False
        self.thread: threading.Thread | None = None
        self.cancel = threading.Event()
        gui.add_markdown("Times every compiled method on a short stretch of this scene against a tight "
                         "reference, then recommends the cheapest that is accurate enough.")
        self.run_btn = gui.add_button("Run speed vs accuracy sweep")
        self.stop_btn = gui.add_button("Stop", disabled=True)
        self.bar = gui.add_progress_bar(0.0)
        tab = results_window.results_tab(gui, "Speed vs accuracy")
        with tab if tab is not None else contextlib.nullcontext():
            self.status = gui.add_markdown("Run the sweep (**Run speed vs accuracy sweep**, in the panel's "
                                           "Speed vs accuracy folder): its chart and recommendation appear here.")
            # aspect is height / width in viser's browser side (see sweep_panel.py); room below for the legend
            self.plot = gui.add_plotly(figure(None), aspect=0.85, config={"displayModeBar": False})
            self.use_btn = gui.add_button(NOTHING_YET, disabled=True)
        self.run_btn.on_click(lambda _: self.start())
        self.stop_btn.on_click(lambda _: self.cancel.set())
        self.use_btn.on_click(lambda _: self.use_recommended())

    def _say(self, text: str) -> None:
        self.status.content = text

    def _say_earlier(self, news: str) -> None:
        """``news`` (a sweep under way or failed) with the earlier result the chart and button still hold."""
        self._say(news + EARLIER + (STALE + "  \n" if self.stale else "") + summary(self.result))

    def start(self) -> threading.Thread | None:
        """Start a sweep in a daemon thread (ignored while one runs); returns the thread."""
        if self.thread is not None and self.thread.is_alive():
            return None
        try:
            sc = self.get_scenario()
        except Exception as exc:  # noqa: BLE001 - the panel reports, never raises into viser
            self._say(f"**Cannot start:** {type(exc).__name__}: {exc}")
            return None
        self.cancel.clear()
        self.bar.value = 0.0
        self.run_btn.disabled = True
        self.stop_btn.disabled = False
        self.use_btn.disabled = True
        if self.result is None:
            self._say("Sweeping ...")
        else:
            self._say_earlier("Sweeping ...")
        self.thread = threading.Thread(target=self._work, args=(sc,), name="speed-vs-accuracy", daemon=True)
        self.thread.start()
        return self.thread

    def _progress(self, fraction: float) -> None:
        self.bar.value = 100.0 * fraction

    def _work(self, sc: physics.Scenario) -> None:
        try:
            result = self.sweep(sc, progress=self._progress, cancel=self.cancel)
            self.result, self.swept, self.stale = result, sc, False
            self.plot.figure = figure(result)
            self._say(summary(result))
            best = result.recommended
            if best is not None:
                self.use_btn.label = f"Use recommended: {METHOD_NAMES.get(best.method, best.method)}, " \
                                     f"{setting_text(best)}"
                self.use_btn.disabled = False
            else:
                self.use_btn.label = NOTHING_YET
            self.bar.value = 100.0
            self.scene_changed()  # the scene may have changed while the sweep ran
        except Exception as exc:  # noqa: BLE001 - a failed sweep is a message, not a dead thread
            failed = f"**Sweep failed:** {results_window.failure(exc)}"
            if self.result is None:
                self._say(failed)
            else:  # the chart still shows the earlier sweep: say so, with its summary, and let it be used again
                self._say_earlier(failed)
                self.use_btn.disabled = self.stale or self.result.recommended is None
        finally:
            self.run_btn.disabled = False
            self.stop_btn.disabled = True

    def refresh(self) -> None:
        """Called by the session after a preset or system change."""
        self.scene_changed()

    def scene_changed(self) -> None:
        """Mark the result stale when the scene differs from the one measured, apart from the run method and
        step (which applying the recommendation changes); the session calls this on every scene change."""
        if self.result is None or self.swept is None:
            return
        try:  # called from the session's loop: never raise into it
            stale = not same_scene(self.swept, self.get_scenario(), ignore=RUN_SETTINGS)
            if stale != self.stale:
                self.stale = stale
                self.plot.figure = figure(self.result, stale=stale)
                # a new sweep under way has its own news (the sweep's own thread calls this once it has ended)
                running = (self.thread is not None and self.thread.is_alive()
                           and self.thread is not threading.current_thread())
                if running:
                    self._say_earlier("Sweeping ...")
                else:
                    self._say((STALE + "  \n" if stale else "") + summary(self.result))
                self.use_btn.disabled = running or stale or self.result.recommended is None
        except Exception:  # noqa: BLE001 - a scenario being swapped out: judged again at the next change
            pass

    def use_recommended(self) -> physics.Scenario | None:
        """Hand the scene's scenario, switched to the recommendation, to ``apply``; returns it."""
        if self.result is None or self.result.recommended is None:
            self._say("Run the sweep first: there is no recommendation yet.")
            return None
        if self.stale:
            self._say(STALE)
            return None
        try:
            sc = self.get_scenario()
            if not self.result.model.startswith(sc.system + "/"):
                raise physics.ScenarioError("scene", sc.system, f"changed since the sweep of {self.result.model}; "
                                            "run the sweep again")
            sc = self.result.apply(sc)
            self.apply(sc)
        except Exception as exc:  # noqa: BLE001 - e.g. the scene changed into one the setting does not fit
            self._say(f"**Cannot use the recommendation:** {type(exc).__name__}: {exc}")
            return None
        self._say(summary(self.result) + "  \nApplied to the scene.")
        return sc
