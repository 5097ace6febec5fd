"""The sweep panel's default ranges and its from/to boxes.

A default range is offered only if every point of it is a valid scene: each candidate point goes
through physics.check_point (the scenario's validation plus the model's own checks, such as
m rho^2/(1 - m/M) < A, which Scenario.from_dict alone does not make). An end that would be invalid is
pulled back towards the scene's current value, to the last valid value found by bisection.
"""

from __future__ import annotations

import math

import numpy as np

import physics

from ..engine import controls

RANGE_FACTOR = 2.0  # the wanted range is value / 2 .. 2 value around the scenario's current value
BISECTIONS = 40  # halvings of the gap between a valid and an invalid end: 2^-40 of it, far below display
SHRINKS = 30  # times the whole range may be pulled halfway back towards the current value
INWARD_DIGITS = 3  # significant digits of an end moved off an invalid value (rounded towards the valid side)
BOX_DIGITS = 6  # decimals a from/to box keeps at least: viser's number box rounds typed input to its precision
MAX_BOX_DIGITS = 12


def scenario_key(slider_key: str, system: str) -> str:
    """The scenario key a slider stands for: the pendulum sliders set every [[plane_pendulum]]."""
    return controls.scenario_key(slider_key, system)


def current_value(sc: physics.Scenario, key: str) -> float:
    """The slider's value in ``sc`` (a value given in words, a tuned spring, as the number it resolves to: the
    system's ``values``)."""
    return controls.values_of(sc).get(key, 0.0)


def wanted_range(sc: physics.Scenario, key: str) -> tuple[float, float]:
    """value / RANGE_FACTOR .. value * RANGE_FACTOR around the current value, or the slider's range at 0."""
    p = controls.BY_KEY[key]
    v = current_value(sc, key)
    if v > 0:
        return v / RANGE_FACTOR, v * RANGE_FACTOR
    if v < 0:
        return v * RANGE_FACTOR, v / RANGE_FACTOR
    return (p.lo, p.hi) if p.hi > p.lo else (0.0, 1.0)


def point_error(sc: physics.Scenario, key: str, value: float) -> str:
    """"" if the scene with ``key`` = ``value`` is valid, else the ScenarioError's message."""
    try:
        physics.check_point(sc, {scenario_key(key, sc.system): float(value)})
    except physics.ScenarioError as exc:
        return str(exc)
    return ""


def _last_valid(sc, key, good: float, bad: float) -> float:
    """The value nearest ``bad`` on the segment good..bad still valid (validity assumed an interval)."""
    for _ in range(BISECTIONS):
        mid = 0.5 * (good + bad)
        if point_error(sc, key, mid):
            bad = mid
        else:
            good = mid
    return good


def _round_towards(x: float, anchor: float) -> float:
    """``x`` to INWARD_DIGITS significant digits, rounded towards ``anchor`` (so it stays on the valid side)."""
    if x == 0 or not math.isfinite(x):
        return x
    scale = 10.0 ** (math.floor(math.log10(abs(x))) - INWARD_DIGITS + 1)
    r = (math.floor if anchor < x else math.ceil)(x / scale) * scale
    return float(f"{r:.{INWARD_DIGITS + 2}g}")


def _nice(x: float) -> float:
    return float(f"{x:.4g}")


def invalid_points(sc, key, lo: float, hi: float, n: int, log: bool = False) -> list[tuple[float, str]]:
    """(value, message) of every point of the range that is not a valid scene."""
    values, _ = physics.axis_values(("log", lo, hi, n) if log else (lo, hi, n), key)
    return [(v, why) for v in values if (why := point_error(sc, key, v))]


def default_range(sc: physics.Scenario, key: str, n: int = 8) -> tuple[float, float]:
    """A range around the scene's value whose ``n`` linearly spaced points are all valid scenes.

    Starts from wanted_range; an invalid end moves back to the last valid value towards the current one
    (bisection), rounded inwards; if a point in between still fails, the range shrinks towards the current
    value. If even the current value fails (a slider at 0 that removes a part), the wanted range is kept:
    the sweep's failed points then say why.
    """
    lo, hi = wanted_range(sc, key)
    lo, hi = _nice(lo), _nice(hi)
    v = current_value(sc, key)
    anchor = min(max(v, lo), hi)
    if point_error(sc, key, anchor):
        valid = [x for x in np.linspace(lo, hi, max(n, 2)) if not point_error(sc, key, x)]
        if not valid:
            return lo, hi
        anchor = valid[len(valid) // 2]
    if point_error(sc, key, lo):
        lo = _round_towards(_last_valid(sc, key, anchor, lo), anchor)
    if point_error(sc, key, hi):
        hi = _round_towards(_last_valid(sc, key, anchor, hi), anchor)
    for _ in range(SHRINKS):
        if not invalid_points(sc, key, lo, hi, n):
            break
        lo, hi = _nice(0.5 * (lo + anchor)), _nice(0.5 * (hi + anchor))
    return lo, hi


def decimals(x: float) -> int:
    """Decimals needed to show ``x`` exactly as typed (at most MAX_BOX_DIGITS)."""
    d = 0
    while d < MAX_BOX_DIGITS and x != round(x, d):
        d += 1
    return d


def box_precision(*values: float) -> int:
    """Decimals for a from/to box: enough for every value, and at least BOX_DIGITS so typing keeps them."""
    return max(BOX_DIGITS, *(decimals(float(v)) for v in values if math.isfinite(float(v))))


def box_step(lo: float, hi: float) -> float:
    """The arrows' step of a from/to box: a tenth of the range's order of magnitude."""
    span = abs(hi - lo) or abs(hi) or 1.0
    return 10.0 ** (math.floor(math.log10(span)) - 1)


def show_range(lo_box, hi_box, lo: float, hi: float) -> None:
    """Put a range into its from/to boxes. viser's number box shows and accepts as many decimals as its precision,
    fixed when it was made from its first value (0 -> whole numbers): the precision is widened before the value."""
    for box, v in ((lo_box, lo), (hi_box, hi)):
        box.precision = box_precision(lo, hi)
        box.step = box_step(lo, hi)
        box.value = v


def reset_range(lo_box, hi_box, get_scenario, key: str | None, n: int) -> None:
    """Fill a from/to pair with ``key``'s default_range of ``n`` points on the current scene; nothing for no key, or
    while the scenario is being swapped out (the old range stays until the next change)."""
    if key is None:
        return
    try:
        lo, hi = default_range(get_scenario(), key, n)
    except Exception:  # noqa: BLE001 - a scenario being swapped out: keep the old range
        return
    show_range(lo_box, hi_box, lo, hi)
