"""The "speed vs accuracy" panel: a work-precision sweep of the current scene (physics.work_precision)
in a background thread, with a progress bar, a log-log chart of theta error against wall time (one
trace per method) and a button that switches the scene to the recommended method and setting.

Nothing here raises into viser: a failed sweep becomes a message in the panel.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable

import physics

NOTHING_YET = "Use recommended: (run the sweep first)"
METHOD_NAMES = {"auto": "DOP853 (compiled, adaptive)", "RK4": "RK4 (compiled)", "RK8": "RK8 (compiled)",
                "midpoint": "implicit midpoint (compiled)"}
ERROR_FLOOR = 1e-16  # rad: a zero error is drawn here on the log axis


def setting_text(row: physics.WorkPrecisionRow) -> str:
    return f"rtol = {row.setting:.3g}" if row.method == "auto" else f"dt = {row.setting:.4g} s"


def figure(result: physics.WorkPrecision | None):
    """A plotly figure: theta error (rad) against wall time (s), log-log, one trace per method, the
    requested tolerance as a dashed line and the recommended point ringed."""
    import plotly.graph_objects as go

    fig = go.Figure()
    if result is not None:
        for method in result.methods():
            rows = sorted((r for r in result.rows if r.method == method), key=lambda r: r.wall_s)
            fig.add_trace(go.Scatter(
                x=[r.wall_s for r in rows], y=[max(r.error, ERROR_FLOOR) for r in rows], mode="lines+markers",
                name=METHOD_NAMES.get(method, method), text=[setting_text(r) for r in rows],
                hovertemplate="%{text}<br>error %{y:.3g} rad<br>%{x:.3g} s<extra></extra>"))
        if math.isfinite(result.tolerance):
            fig.add_hline(y=result.tolerance, line_dash="dash", line_color="gray",
                          annotation_text="requested", annotation_position="top left")
        best = result.recommended
        if best is not None:
            fig.add_trace(go.Scatter(x=[best.wall_s], y=[max(best.error, ERROR_FLOOR)], mode="markers",
                                     name="recommended", marker={"size": 14, "symbol": "circle-open",
                                                                  "line": {"width": 2}}))
    fig.update_xaxes(type="log", title_text="wall time (s)")
    fig.update_yaxes(type="log", title_text="theta error (rad)")
    fig.update_layout(margin={"l": 50, "r": 10, "t": 10, "b": 40}, legend={"font": {"size": 9}})
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
        self.thread: threading.Thread | None = None
        self.cancel = threading.Event()
        self.status = gui.add_markdown("Times every compiled method on a short stretch of this scene against a "
                                       "tight reference, then recommends the cheapest that is accurate enough.")
        self.run_btn = gui.add_button("Run speed vs accuracy sweep")
        self.stop_btn = gui.add_button("Stop", disabled=True)
        self.bar = gui.add_progress_bar(0.0)
        self.plot = gui.add_plotly(figure(None), aspect=1.3)
        self.use_btn = gui.add_button(NOTHING_YET, disabled=True)
        self.run_btn.on_click(lambda _: self.start())
        self.stop_btn.on_click(lambda _: self.cancel.set())
        self.use_btn.on_click(lambda _: self.use_recommended())

    def _say(self, text: str) -> None:
        self.status.content = text

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
        self._say("Sweeping ...")
        self.thread = threading.Thread(target=self._work, args=(sc,), name="speed-vs-accuracy", daemon=True)
        self.thread.start()
        return self.thread

    def _progress(self, fraction: float) -> None:
        self.bar.value = 100.0 * fraction

    def _work(self, sc: physics.Scenario) -> None:
        try:
            result = self.sweep(sc, progress=self._progress, cancel=self.cancel)
            self.result = result
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
        except Exception as exc:  # noqa: BLE001 - a failed sweep is a message, not a dead thread
            self._say(f"**Sweep failed:** {type(exc).__name__}: {exc}")
        finally:
            self.run_btn.disabled = False
            self.stop_btn.disabled = True

    def use_recommended(self) -> physics.Scenario | None:
        """Hand the scene's scenario, switched to the recommendation, to ``apply``; returns it."""
        if self.result is None or self.result.recommended is None:
            self._say("Run the sweep first: there is no recommendation yet.")
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
