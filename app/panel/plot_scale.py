"""What a chart's y axis plots, so that its tick labels are short, exact and distinct.

uPlot formats a tick with at most 3 decimals and draws it right-aligned in an axis of fixed width. A
series that barely varies (|K| = 3.58 +- 1e-9, E = 309.30..309.34) then gets ticks that all print alike
("0.696 0.696 0.696"), and a large value ("455.00001") is longer than the axis and gets cut ("0"). So the
server chooses, from the data, a reference to subtract (shown in the label: "|K| - 3.58") and a power of
ten to divide by ("x1e-9"), such that the plotted span is at least SPAN_MIN and the plotted values are at
most MAG_MAX and at most RATIO times the span. The ticks then need at most 3 decimals and 6 digits. A
choice is kept while the data still fit it: a label that changed every update would be unreadable (and
uPlot rebuilds a chart whose labels change).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

SPAN_MIN = 0.05  # plotted units: ticks 0.01 apart or more, exact with 3 decimals
MAG_MAX = 1e4  # plotted units: labels of at most 4 digits before the point ("9,999")
RATIO = 100.0  # largest plotted magnitude / plotted span: at most about 5 significant digits per label
CONSTANT = 1e-12  # relative spread below which a series is constant (rounding noise of the integrator)
EXP_MIN = -300  # smallest power of ten a scale divides by: 10.0**-324 is 0.0, and theta0 = 1e-320 gives such data
TINY = 1e-290  # a span below this is drawn as constant: no round step exists among subnormal numbers


@dataclass(frozen=True)
class AxisScale:
    """The plotted value is (value - offset) / 10**exp; ``flat``: the series is constant to CONSTANT and is
    drawn as its first value."""

    offset: float = 0.0
    exp: int = 0
    flat: bool = False

    def apply(self, y: np.ndarray) -> np.ndarray:
        y = np.asarray(y, dtype=float)
        if self.flat and len(y):
            y = np.full_like(y, y[0])
        return (y - self.offset) / 10.0**self.exp

    def label(self, symbol: str, unit: str) -> str:
        """The series' name as plotted: "E (J)", "E (x1e-3 J)", "|K| - 3.58 (x1e-9 kg m²/s)"."""
        head = symbol if self.offset == 0 else f"{symbol} − {_short(self.offset)}"
        unit = unit if self.exp == 0 else f"×1e{self.exp} {unit}"
        return f"{head} ({unit})" + (", constant" if self.flat else "")

    def fits(self, lo: float, hi: float, first: float) -> bool:
        """Whether data spanning lo..hi still plot with good ticks under this scale, and no simpler scale
        (no reference, or no power of ten) would do. Its limits are looser than choose()'s: data that
        wander about a limit do not switch the scale back and forth."""
        if not (math.isfinite(lo) and math.isfinite(hi) and math.isfinite(first)):
            return False
        span, mag = hi - lo, max(abs(lo), abs(hi))
        if self.flat or _constant(span, mag):
            return self.flat and _constant(span, mag) and self.exp == _exp_for(mag)
        fresh = choose(lo, hi, first)
        if (self.offset and not fresh.offset) or (self.exp and not fresh.exp):
            return False
        k = 10.0**self.exp
        span_p, mag_p = span / k, max(abs(lo - self.offset), abs(hi - self.offset)) / k
        return span_p >= SPAN_MIN / 5 and mag_p < MAG_MAX and mag_p <= RATIO * span_p


def choose(lo: float, hi: float, first: float) -> AxisScale:
    """The scale for data spanning lo..hi whose first value is ``first`` (the reference an offset rounds)."""
    if not (math.isfinite(lo) and math.isfinite(hi) and math.isfinite(first)) or hi < lo:
        return AxisScale()
    span, mag = hi - lo, max(abs(lo), abs(hi))
    if _constant(span, mag):
        return AxisScale(exp=_exp_for(mag), flat=True)
    if mag <= RATIO * span:  # varies visibly: plot the values, in a power of ten if they are small or large
        if span >= SPAN_MIN and mag < MAG_MAX:
            return AxisScale()
        return AxisScale(exp=_eng(mag))
    # nearly constant: subtract a round reference near the start
    q = 10.0 ** max(math.floor(math.log10(span)), EXP_MIN)
    offset = float(round(first / q) * q)
    dev = max(abs(lo - offset), abs(hi - offset))  # at most span + q / 2 <= 1.5 span
    if span >= SPAN_MIN and dev < MAG_MAX:
        return AxisScale(offset=offset)
    return AxisScale(offset=offset, exp=_eng(dev))


class ScaleKeeper:
    """One chart's current scale: kept while the data fit it, chosen anew when they do not."""

    def __init__(self):
        self.scale = AxisScale()
        self._chosen = False

    def update(self, *series: np.ndarray) -> bool:
        """Fit the scale to the series (same length); returns whether it changed."""
        ys = [np.asarray(s, dtype=float) for s in series if len(s)]
        if not ys:
            return False
        lo = min(float(np.min(y)) for y in ys)
        hi = max(float(np.max(y)) for y in ys)
        if self._chosen and self.scale.fits(lo, hi, float(ys[0][0])):
            return False
        new = choose(lo, hi, float(ys[0][0]))
        changed = new != self.scale
        self.scale, self._chosen = new, True
        return changed


def y_range(lo: float, hi: float) -> tuple[float, float]:
    """The y axis's extent for plotted values lo..hi: 2 % of the span beyond each, then out to a multiple of
    a round step of about a third of it, so the axis ends on ticks and shows two to four of them; a flat
    line gets 10 % of its value (or 1) on each side. Data that never go below 0 (or above it) get an axis that
    does not either: theta decaying to 0.004 rad drew its axis down to -0.2, a third of the chart for values it
    cannot take. The server sets it (and the x extent): uPlot's own ranging of the x axis, under viser 1.1.1's
    zoom keeping, drifted off the data on a busy page (the plot showed t = 0..2 s at t = 13 s)."""
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi < lo:
        return -1.0, 1.0
    given = (lo, hi) if lo < hi else (math.nextafter(lo, -math.inf), math.nextafter(hi, math.inf))
    positive, negative = lo >= 0, hi <= 0
    if hi - lo <= max(CONSTANT * max(abs(lo), abs(hi)), TINY):
        pad = 0.1 * abs(lo) if abs(lo) > TINY else 1.0
        lo, hi = lo - pad, hi + pad
    span = hi - lo
    if not math.isfinite(span):  # padding overflowed: values near 1e308
        return given
    lo, hi = lo - 0.02 * span, hi + 0.02 * span
    if positive:
        lo = max(lo, 0.0)
    elif negative:
        hi = min(hi, 0.0)
    step = _round_up((hi - lo) / 3)
    out = math.floor(lo / step) * step, math.ceil(hi / step) * step
    return out if math.isfinite(out[0]) and math.isfinite(out[1]) else given


def _round_up(x: float) -> float:
    """The smallest of 1, 2, 5 times a power of ten that is at least x."""
    p = 10.0 ** math.floor(math.log10(x))
    return next(m * p for m in (1, 2, 5, 10) if m * p >= x * (1 - 1e-12))


def _constant(span: float, mag: float) -> bool:
    return span <= CONSTANT * mag or mag == 0.0


def _exp_for(mag: float) -> int:
    """A constant's power of ten: none when it prints short."""
    return 0 if mag == 0.0 or 1e-2 <= mag < MAG_MAX else _eng(mag)


def _eng(x: float) -> int:
    """The multiple of 3 at or below log10(x): the plotted magnitude is then 1 to 1000."""
    return max(3 * math.floor(math.log10(x) / 3), EXP_MIN)


def _short(x: float) -> str:
    """A reference as typed: no trailing zeros, no float noise (round() left 3.5800000000000001)."""
    return f"{x:.12g}"
