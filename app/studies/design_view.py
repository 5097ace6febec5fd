"""What the Design window shows of a design (physics.DesignResult): the objective run by run with the best so far,
and the optimum in words beside the papers' tunings. Plain functions of the result; no widgets here."""

from __future__ import annotations

import math

import numpy as np

import physics

from ..engine import controls
from .results_window import blank_chart

GOAL_WORDS = {"min_positive": "smallest positive", "max": "largest", "min": "smallest"}
PHASE_COLOURS = {"start": "#7f7f7f", "refine 1": "#1f77b4", "refine 2": "#2ca02c", "check": "#d62728"}


def _num(x: float) -> str:
    return controls.fmt(x, 5) if math.isfinite(x) else str(x)


def named(slider: str, value: float) -> str:
    """"k = 41.56 N m/rad" for a slider key."""
    p = controls.BY_KEY[slider]
    return f"{p.label} = {_num(value)}" + (f" {p.unit}" if p.unit else "")


def best_so_far(path, goal: str) -> np.ndarray:
    """The best objective up to each run of ``path`` (Evaluations), as the design ranks them (NaN before the first
    that counts)."""
    out, best = [], math.nan
    for e in path:
        v = e.objective
        counts = math.isfinite(v) and (goal != "min_positive" or v > 0)
        if counts and (math.isnan(best) or (v > best if goal == "max" else v < best)):
            best = v
        out.append(best)
    return np.array(out)


def figure(result: physics.DesignResult | None, stale: bool = False):
    """The finished design's runs (for None, a blank chart saying what it will show)."""
    if result is None:
        return blank_chart("each run's objective, drawn as the design runs")
    return path_figure(result.path, result.goal, result.objective, result.unit, stale)


def path_figure(path, goal: str, objective: str, unit: str, stale: bool = False):
    """Each run's objective, coloured by phase, and the best so far: drawn as the runs come and when done."""
    import plotly.graph_objects as go

    fig = go.Figure()
    fig.update_layout(margin={"l": 10, "r": 10, "t": 30, "b": 10}, legend={"orientation": "h", "y": -0.25},
                      font={"size": 11})
    if not path:
        return fig
    runs = np.arange(1, len(path) + 1)
    values = np.array([e.objective for e in path])
    for phase in dict.fromkeys(e.phase for e in path):
        mask = np.array([e.phase == phase for e in path])
        fig.add_trace(go.Scatter(x=runs[mask], y=values[mask], mode="markers", name=phase,
                                 marker={"size": 6, "color": PHASE_COLOURS.get(phase)}))
    fig.add_trace(go.Scatter(x=runs, y=best_so_far(path, goal), mode="lines", name="best so far",
                             line={"color": "black", "width": 2}))
    positive = values[np.isfinite(values) & (values > 0)]
    log = len(positive) > 1 and positive.max() / positive.min() > 30
    fig.update_yaxes(title_text=objective + (f" ({unit})" if unit else ""), type="log" if log else "linear")
    title = f"{objective} by run (x: the run's number)" + (" (stale: the scene has changed)" if stale else "")
    fig.update_layout(title={"text": title, "x": 0.02, "font": {"size": 12}})
    return fig


def summary(result: physics.DesignResult, sliders: dict[str, str]) -> str:
    """The optimum, its value from the full model, the runs, and the papers' tunings beside it (markdown).
    ``sliders`` maps each scenario key the design varied to its slider."""
    unit = f" {result.unit}" if result.unit else ""
    best = ", ".join(named(sliders[k], v) for k, v in result.best.items())
    lines = [f"**Optimum** ({result.objective}, {GOAL_WORDS[result.goal]}): {best}"]
    if math.isfinite(result.value):
        lines.append(f"{result.objective} = **{_num(result.value)}{unit}** from the full model")
    else:
        lines.append(f"{result.objective} = {_num(result.cheap_value)}{unit} from {result.best_model} (stopped "
                     "before the full model's check)")
    edges = [sliders[k] for (k, v), (lo, hi) in zip(result.best.items(), result.bounds, strict=True) if v in (lo, hi)]
    if edges:
        lines.append("On the edge of its range: " + ", ".join(controls.BY_KEY[s].label for s in edges)
                     + "; a wider range may hold a better point")
    lines.append(f"{result.evaluations} runs in {result.wall_s:.1f} s" + (" (stopped)" if result.stopped else ""))
    for name, (values, value) in result.references.items():
        words = ", ".join(named(sliders.get(k, k), v) if sliders.get(k, k) in controls.BY_KEY else f"{k} = {v:.5g}"
                          for k, v in values.items())
        lines.append(f"{name}: {words}: {result.objective} = {_num(value)}{unit}")
    return "  \n".join(lines)
