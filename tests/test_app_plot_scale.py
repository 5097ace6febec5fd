"""The plots' y scales (app/panel/plot_scale.py): whatever the data, the ticks uPlot draws are short, exact and
distinct. uPlot's tick choice is imitated here (the smallest allowed step that leaves ``space`` pixels
between ticks, labels printed with at most 3 decimals, as Intl.NumberFormat does); the browser test
tests/test_app_browser_plots.py reads the real ones off the page."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app.panel.plot_scale import AxisScale, ScaleKeeper, choose, y_range
from app.panel.plots import INCRS

CHART_PX = 90  # the smallest y extent of a chart in the panel (|K| and E: aspect 3.5)
SPACE_PX = 30  # uPlot's default minimum space between y ticks
LABEL_CHARS = 7  # app.panel.plots.Y_AXIS_PX is sized for this many


def fmt(x: float) -> str:
    """Intl.NumberFormat("en-US").format: grouping, at most 3 fraction digits, no trailing zeros."""
    s = f"{x:,.3f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def drawn_ticks(y: np.ndarray) -> list[str]:
    lo, hi = float(np.min(y)), float(np.max(y))
    if hi == lo:  # uPlot pads a constant series by its own magnitude (or 1 around zero)
        pad = abs(lo) or 1.0
        lo, hi = lo - pad, hi + pad
    incr = next(i for i in INCRS if i * CHART_PX / (hi - lo) >= SPACE_PX)
    first = math.ceil(lo / incr - 1e-9)
    return [fmt(k * incr) for k in range(first, math.floor(hi / incr + 1e-9) + 1)]


def check(y: np.ndarray) -> AxisScale:
    keeper = ScaleKeeper()
    keeper.update(y)
    plotted = keeper.scale.apply(y)
    labels = drawn_ticks(plotted)
    assert len(labels) >= 1
    assert len(set(labels)) == len(labels), labels  # distinct
    assert max(len(s) for s in labels) <= LABEL_CHARS, labels  # fits the axis
    return keeper.scale


@pytest.mark.parametrize("lo, hi", [
    (309.30, 309.34),  # the E = 309.3 ("09.34")
    (300.09, 300.0901),  # E = 300.09 ("0.094")
    (455.0, 455.0 + 1e-9),  # |K| = 455 ("0")
    (0.696, 0.696 + 3e-7),  # "0.696 0.696 0.696"
    (0.2, 0.87),  # theta of the default scene
    (0.059, 4.36),  # its E
    (-2.5e-6, 1.5e-6),  # a small deviation about zero
    (1.0e6, 3.0e6),  # a large energy
    (12345.6, 12345.7),
    (-455.0 - 1e-6, -455.0),
])
def test_ticks_are_distinct_and_short(lo, hi):
    check(np.linspace(lo, hi, 50))


@pytest.mark.parametrize("value", [0.0, 3.58, 455.0, -7.0, 2.5e7, 4e-5])
def test_a_constant_is_drawn_flat_with_its_value(value):
    y = value * (1.0 + 1e-14 * np.sin(np.arange(100)))  # rounding noise of the integrator
    scale = check(y)
    assert scale.flat
    assert np.ptp(scale.apply(y)) == 0.0
    assert scale.apply(y)[0] * 10.0**scale.exp + scale.offset == pytest.approx(value, rel=1e-12, abs=1e-300)


def test_the_label_names_the_reference_and_the_power():
    s = choose(3.58, 3.58 + 2e-9, 3.58)
    assert s.offset == pytest.approx(3.58) and s.exp == -9
    assert s.label("|K|", "kg m²/s") == "|K| − 3.58 (×1e-9 kg m²/s)"
    assert choose(0.2, 0.87, 0.87).label("theta", "rad") == "theta (rad)"
    assert choose(1e6, 3e6, 1e6).label("E", "J") == "E (×1e6 J)"


def test_a_scale_is_kept_while_the_data_fit_and_a_simpler_one_is_taken_when_they_allow():
    keeper = ScaleKeeper()
    assert keeper.update(np.array([3.58, 3.58 + 2e-9]))
    first = keeper.scale
    assert not keeper.update(np.array([3.58, 3.58 + 3e-9]))  # still fits: no relabelling each update
    assert keeper.scale is first
    assert keeper.update(np.array([1.0, 3.58]))  # braking: |K| now varies visibly, plain values again
    assert keeper.scale == AxisScale()


@settings(max_examples=300, deadline=None)
@given(center=st.floats(-1e9, 1e9), rel=st.floats(-16, 2), n=st.integers(2, 40))
def test_any_series_gets_good_ticks(center, rel, n):
    span = max(abs(center), 1e-6) * 10.0**rel
    y = center + span * np.sin(np.linspace(0.0, 3.0, n))
    check(y)


MAGNITUDES = (0.0, 5e-324, 1e-323, 3e-322, 1e-310, 2.2250738585072014e-308, 1e-300, 1e-12, 1.0, 1e300, 1e308,
              1.7976931348623157e308)
VALUES = sorted({s * m for m in MAGNITUDES for s in (1.0, -1.0)})


@pytest.mark.parametrize("lo", VALUES)
def test_data_of_any_finite_magnitude_get_a_finite_plot_and_axis(lo):
    """A hostile parameter (m = 5e-324, Omega = 1e308) gives a series of subnormal or huge values; the server's
    storm once died here on 10.0**-324 == 0.0 (ZeroDivisionError). Every pair of values as the data, then every
    other pair on the kept scale: no exception, finite plotted values and a finite axis around them."""
    for hi in (v for v in VALUES if v >= lo):
        keeper = ScaleKeeper()
        for later in ((lo, hi), (hi, lo), *((a, b) for a in VALUES[::3] for b in VALUES[::4] if a <= b)):
            y = np.array([later[0], later[0] / 2 + later[1] / 2, later[1]])  # no overflow midway
            keeper.update(y)
            plotted = keeper.scale.apply(y)
            assert np.all(np.isfinite(plotted)), (later, keeper.scale, plotted)
            bottom, top = y_range(float(plotted.min()), float(plotted.max()))
            assert math.isfinite(bottom) and math.isfinite(top) and bottom < top, (later, bottom, top)
            assert bottom <= plotted.min() and plotted.max() <= top
            assert keeper.scale.label("E", "J").startswith("E")


@pytest.mark.parametrize("bad", [math.inf, -math.inf, math.nan])
def test_a_non_finite_value_in_the_data_raises_nothing(bad):
    keeper = ScaleKeeper()
    keeper.update(np.array([1.0, 2.0]))
    keeper.update(np.array([1.0, bad]))  # a fault's last sample: the run stops on it, the chart must not
    assert keeper.scale == AxisScale()
    assert y_range(1.0, bad) == (-1.0, 1.0)


@pytest.mark.parametrize("lo, hi", [(-1.7976931348623157e308, 1.7976931348623157e308), (1e308, 1e308),
                                    (5e-324, 5e-324), (0.0, 5e-324), (-1e-320, 1e-320)])
def test_the_axis_around_extreme_plotted_values_is_finite_and_holds_them(lo, hi):
    bottom, top = y_range(lo, hi)
    assert math.isfinite(bottom) and math.isfinite(top) and bottom < top and bottom <= lo and hi <= top


@pytest.mark.parametrize("lo, hi, bottom, top", [
    (0.0044, 0.3, 0.0, None),  # theta settling towards 0: the axis ended at -0.2, a third of the chart below 0
    (0.0, 0.0, 0.0, None), (0.0, 5e-324, 0.0, None), (1e-300, 1e-290, 0.0, None),
    (-0.3, -0.0044, None, 0.0),  # and the mirror image
    (-0.1, 0.3, -0.2, 0.4),  # data on both sides of 0: as before
])
def test_data_that_never_cross_zero_get_an_axis_that_does_not_either(lo, hi, bottom, top):
    got = y_range(lo, hi)
    assert got[0] <= lo and hi <= got[1] and got[0] < got[1], got
    if bottom is not None:
        assert got[0] == bottom, got
    if top is not None:
        assert got[1] == top, got
