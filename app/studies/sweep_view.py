"""What a finished sweep shows: which point is best for its metric, why points failed, and the chart.

"Best" is what a user tuning a damper wants, per metric (GOALS): for decay_time the fastest decay among
the points whose nutation decays (tau > 0; tau < 0 grows, inf is flat), never the most negative tau.
The colour scale copes with outliers: a positive metric spanning more than LOG_SPAN is coloured by its
logarithm, otherwise the colours are clipped to Tukey's fences around the middle half of the values;
the colour bar's title says which. A decay_time heat map is coloured by the decay rate 1/tau (see
``coloured``): blue decays, red grows, its caption saying which the cells shown are (``rate_colours``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import physics

from ..engine import controls
from .slider_choice import scenario_text


@dataclass(frozen=True)
class Goal:
    """``larger``: bigger is better; ``admits(v)``: the values that can be best; ``text``: the rule in words."""

    larger: bool
    admits: object
    text: str


def _finite(v: float) -> bool:
    return math.isfinite(v)


GOALS: dict[str, Goal] = {
    "decay_time": Goal(False, lambda v: math.isfinite(v) and v > 0,
                       "fastest decay: the smallest tau among the points whose nutation decays "
                       "(tau > 0 decays, tau < 0 grows)"),
    "theta_end": Goal(False, _finite, "smallest nutation angle at the end of the run"),
    "braking_time": Goal(False, _finite, "quickest stop by braking (inf: not stopped by t_end)"),
    "max_displacement": Goal(False, _finite, "smallest excursion of the internal part"),
    "energy_dissipated": Goal(True, _finite, "most energy dissipated"),
}
DEFAULT_GOAL = Goal(False, _finite, "smallest value")
LOG_SPAN = 30.0  # max/min of a positive metric beyond which its colours follow its logarithm
FENCE = 3.0  # Tukey's far-out fence: colours are clipped to [q1 - 3 IQR, q3 + 3 IQR]


def goal(metric: str) -> Goal:
    return GOALS.get(metric, DEFAULT_GOAL)


def failure(row: dict) -> str:
    """Why a point failed, as the user reads it: the ScenarioError's own message (key, value, allowed)."""
    err = row.get("error", "")
    for prefix in ("ScenarioError: ",):
        if err.startswith(prefix):
            return err[len(prefix):]
    return err


def _numbers(rows: list[int]) -> str:
    return ", ".join(f"#{i}" for i in rows[:6]) + (" ..." if len(rows) > 6 else "")


def ranked(table: physics.SweepTable) -> list[int]:
    """Row indices: the admissible points best first, then the other finite ones (e.g. growing), then failed."""
    g = goal(table.metric)

    def order(i):
        v = table.rows[i][table.metric]
        if g.admits(v):
            return (0, -v if g.larger else v, i)
        if math.isfinite(v):
            return (1, v, i)
        return (2, 0.0, i)

    return sorted(range(len(table.rows)), key=order)


def best(table: physics.SweepTable) -> int | None:
    """The best row by the metric's goal, or None when no point qualifies."""
    order = ranked(table)
    return order[0] if order and goal(table.metric).admits(table.rows[order[0]][table.metric]) else None


def where(table: physics.SweepTable, i: int) -> str:
    row = table.rows[i]
    return ", ".join(f"{k.split('.', 1)[1]} = {row[k]:.4g}" for k in table.keys)


def point_label(table: physics.SweepTable, i: int) -> str:
    """A dropdown entry: the point and its metric value, or why it failed."""
    row = table.rows[i]
    v = row[table.metric]
    if row["error"]:
        shown = "failed: " + failure(row)
    elif table.metric == "decay_time" and math.isfinite(v) and v < 0:
        shown = f"{controls.fmt(v)} (grows)"
    else:
        shown = controls.fmt(v)
    return f"#{i}: {where(table, i)} -> {table.metric} {shown}"


def estimate_line(table: physics.SweepTable) -> str:
    """Which model the points ran and the theta error each states against the full model (physics'
    ``error_bound``), with how it was obtained."""
    ran = [r for r in table.rows if r["model"] and not r["error"]]
    cheap = [r for r in ran if not r["model"].endswith("/full")]
    if not cheap:
        return "Every point ran the full model (the reference)." if ran else ""
    worst = max(float(r.get("error_bound", math.nan)) for r in cheap)
    how = table.info.get("error_bound_method", "")
    return (f"{len(cheap)} of {len(ran)} point(s) ran a cheaper model; the theta error they state against the full "
            f"model is at most {worst:.2g} rad" + (f" (estimate: {how})." if how else "."))


def summary(table: physics.SweepTable) -> str:
    """Markdown: the best point with the rule that chose it, then what was left out and why points failed."""
    unit = physics.METRICS[table.metric].unit
    g = goal(table.metric)
    b = best(table)
    lines = [f"**Best** ({g.text}): "
             + (f"{table.metric} = {controls.fmt(table.rows[b][table.metric])} {unit} at {where(table, b)} "
                f"(#{b})" if b is not None else "none of the points qualifies")]
    values = table.column(table.metric)
    if table.metric == "decay_time":
        grows = int(np.sum(np.isfinite(values) & (values < 0)))
        flat = int(np.sum(np.isinf(values)))
        if grows or flat:
            lines.append(f"Left out: {grows} point(s) where the nutation grows (tau < 0)"
                         + (f", {flat} flat (tau = inf)" if flat else "") + ".")
    lines.append(estimate_line(table))
    reasons: dict[str, list[int]] = {}
    unrun = []
    for i, row in enumerate(table.rows):
        if table.not_run(row):
            unrun.append(i)
        elif row["error"]:
            reasons.setdefault(failure(row), []).append(i)
    for why, rows in reasons.items():
        lines.append(f"{len(rows)} point(s) failed ({_numbers(rows)}): {why}")
    if unrun:
        lines.append(f"{len(unrun)} point(s) not run ({_numbers(unrun)}): the sweep was stopped first")
    return "  \n".join(lines)


@dataclass(frozen=True)
class ColourScale:
    """How values become colours: ``kind`` "log", "clipped" or "linear"; ``lo``/``hi`` the coloured span
    (in the metric's units); ``title`` says so on the colour bar."""

    kind: str
    lo: float
    hi: float
    title: str

    def apply(self, v: float) -> float | None:
        """The number the colour map receives for ``v`` (None for a failed point: left blank)."""
        if not math.isfinite(v):
            return None
        if self.kind == "log":
            return math.log10(v)
        return min(max(v, self.lo), self.hi)


def colour_scale(values, unit: str) -> ColourScale:
    """Log colours for a positive metric spanning over LOG_SPAN; otherwise linear, clipped to Tukey's fences
    when values lie beyond them, so one outlier cannot wash out every other cell."""
    v = np.asarray([x for x in values if math.isfinite(x)], dtype=float)
    if v.size == 0:
        return ColourScale("linear", 0.0, 1.0, unit)
    lo, hi = float(v.min()), float(v.max())
    if lo > 0 and hi / lo > LOG_SPAN:
        return ColourScale("log", lo, hi, f"{unit}, log scale")
    q1, q3 = np.percentile(v, [25, 75])
    f_lo, f_hi = q1 - FENCE * (q3 - q1), q3 + FENCE * (q3 - q1)
    if (lo < f_lo or hi > f_hi) and f_hi > f_lo:
        c_lo, c_hi = max(lo, float(f_lo)), min(hi, float(f_hi))
        return ColourScale("clipped", c_lo, c_hi,
                           f"{unit}, clipped to {controls.fmt(c_lo, 3)}..{controls.fmt(c_hi, 3)}")
    return ColourScale("linear", lo, hi, unit)


RATE_TITLE = "1/tau (1/s)"  # the colour bar's; the chart's title says what the sign means


def coloured(table: physics.SweepTable) -> tuple[np.ndarray, str, bool]:
    """(values the heat map colours, their colour-bar title, diverging around 0?). decay_time is coloured
    by its rate 1/tau: continuous through a flat run (tau = inf is rate 0) and through growth (rate < 0),
    so a near-flat cell of tau = 250,000 s is a rate near 0, not an outlier that flattens every colour."""
    values = table.column(table.metric)
    if table.metric == "decay_time":
        with np.errstate(divide="ignore"):
            return np.where(np.isinf(values), 0.0, 1.0 / values), RATE_TITLE, True
    return values, physics.METRICS[table.metric].unit, False


# blue for a decay (rate > 0), red for growth (rate < 0), white for flat; written out, so that which end is which
# does not hang on a library's naming (plotly.py's "RdBu" runs red to blue, plotly.js's blue to red)
BLUES = [[0.0, "rgb(247,251,255)"], [0.5, "rgb(107,174,214)"], [1.0, "rgb(8,48,107)"]]
REDS = [[0.0, "rgb(103,0,13)"], [0.5, "rgb(239,59,44)"], [1.0, "rgb(255,245,240)"]]
RED_WHITE_BLUE = [[0.0, "rgb(178,24,43)"], [0.5, "rgb(247,247,247)"], [1.0, "rgb(33,102,172)"]]


def rate_colours(rates, what: str) -> tuple[ColourScale, dict, str]:
    """(scale, the heat map's colour settings, its caption) for decay rates 1/tau: the colours say the sign, and
    the caption says what they mean for the cells shown. Every point decaying (or flat): blues, darker decays
    faster, a log scale when the rates span more than LOG_SPAN; every point growing: reds, darker grows faster;
    both: red, white at 0, blue, on a linear (clipped) scale centred on 0, so no transform moves a cell across 0."""
    r = np.asarray([x for x in rates if math.isfinite(x)], dtype=float)
    if r.size == 0 or r.min() >= 0:
        return (colour_scale(rates, what), {"colorscale": BLUES},
                "decay rate 1/tau: every point decays, darker decays faster")
    if r.max() <= 0:
        return (colour_scale(rates, what), {"colorscale": REDS},
                "decay rate 1/tau: every point grows (rate < 0), darker grows faster")
    return colour_scale(rates, what), {"colorscale": RED_WHITE_BLUE, "zmid": 0.0}, \
        "decay rate 1/tau: blue decays, red grows, white is flat"


def _decades(lo: float, hi: float) -> list[float]:
    a, b = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
    return [float(e) for e in range(a, b + 1)]


def figure(table: physics.SweepTable, stale: bool = False):
    """A plotly figure: the curve (one key) or the heat map (two keys) of the table's metric, the best point
    marked; a heat map's colour scale per colour_scale."""
    import plotly.graph_objects as go

    metric, unit = table.metric, physics.METRICS[table.metric].unit
    values = table.column(metric)
    b = best(table)
    names = [scenario_text(k, table.base.system) for k in table.keys]  # "m (kg)", as the panel's sliders read
    fig = go.Figure()
    if len(table.keys) == 1:
        x = list(table.axes[0])
        y = [v if math.isfinite(v) else None for v in values]
        fig.add_trace(go.Scatter(x=x, y=y, mode="lines+markers", name=metric, showlegend=False,
                                 hovertemplate=f"{names[0]} = %{{x:.4g}}<br>{metric} = %{{y:.4g}}<extra></extra>"))
        if b is not None:
            fig.add_trace(go.Scatter(x=[x[b]], y=[values[b]], mode="markers", name="best", showlegend=False,
                                     marker={"size": 14, "symbol": "circle-open", "line": {"width": 2}}))
        fig.update_xaxes(title_text=names[0], type="log" if table.spacing[0] == "log" else "linear")
        scale = colour_scale(values, unit)
        fig.update_yaxes(title_text=f"{metric} ({scale.title})", type="log" if scale.kind == "log" else "linear")
        if scale.kind == "clipped":  # the outliers run off the chart instead of flattening the rest
            pad = 0.05 * (scale.hi - scale.lo)
            fig.update_yaxes(range=[scale.lo - pad, scale.hi + pad])
    else:
        n1, n2 = table.shape
        shown, what, diverging = coloured(table)
        heat, caption = {"colorscale": "Viridis"}, ""
        if diverging:
            scale, heat, caption = rate_colours(shown, what)
        else:
            scale = colour_scale(shown, what)
        z = np.array([scale.apply(v) for v in shown], dtype=object).reshape(n1, n2).tolist()
        text = np.array([f"{metric} = {controls.fmt(v)} {unit}" if not table.rows[i]["error"] and not math.isnan(v)
                         else ("failed" if table.rows[i]["error"] else "n/a") for i, v in enumerate(values)],
                        dtype=object).reshape(n1, n2).tolist()
        bar = {"title": {"text": scale.title, "side": "right", "font": {"size": 11}}}
        if scale.kind == "log":
            ticks = _decades(scale.lo, scale.hi)
            bar.update(tickvals=ticks, ticktext=[controls.fmt(10.0 ** t, 3) for t in ticks])
        fig.add_trace(go.Heatmap(x=list(table.axes[1]), y=list(table.axes[0]), z=z, text=text, colorbar=bar,
                                 hovertemplate=(f"{names[1]} = %{{x:.4g}}<br>{names[0]} = "
                                                "%{y:.4g}<br>%{text}<extra></extra>"), **heat))
        if b is not None:
            a_, c_ = divmod(b, n2)
            fig.add_trace(go.Scatter(x=[table.axes[1][c_]], y=[table.axes[0][a_]], mode="markers", name="best",
                                     showlegend=False, hoverinfo="skip",
                                     marker={"size": 16, "symbol": "circle-open", "color": "red",
                                             "line": {"width": 3}}))
        fig.update_xaxes(title_text=names[1], type="log" if table.spacing[1] == "log" else "linear")
        fig.update_yaxes(title_text=names[0], type="log" if table.spacing[0] == "log" else "linear")
    title = metric
    if len(table.keys) > 1 and caption:
        title = caption
    title += (", best ringed" if b is not None else "") + (" - STALE: the scene changed" if stale else "")
    fig.update_layout(title={"text": title, "font": {"size": 13}}, margin={"l": 60, "r": 10, "t": 34, "b": 44})
    return fig
