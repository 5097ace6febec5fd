"""A tab's frame rate (app.serve.pace): what the tabs' loops ask of the server's one interpreter stays within
SHARE of a core, so viser's sender keeps up and a tab receives the frames it is published (tests/test_load.py
measures that end to end). Counts and rates from given costs: no clock is read."""

from __future__ import annotations

import pytest

from app.engine.clock import FRAME_HZ
from app.serve.pace import CROWD, CROWD_HZ, MIN_HZ, SHARE, Pace


def _paced(cost_s: float) -> Pace:
    pace = Pace()
    for _ in range(200):
        pace.spent(cost_s)
    return pace


def test_a_tab_that_has_not_measured_a_frame_yet_gets_the_full_rate():
    assert Pace().hz(1) == FRAME_HZ and Pace().hz(CROWD + 1) == CROWD_HZ


@pytest.mark.parametrize("tabs", [1, 4, 5, 10, 30])
@pytest.mark.parametrize("cost_ms", [0.5, 1.0, 2.5, 10.0, 80.0])
def test_the_tabs_together_ask_at_most_their_share_of_a_core_unless_at_the_floor(tabs, cost_ms):
    hz = _paced(cost_ms / 1e3).hz(tabs)
    assert MIN_HZ <= hz <= (FRAME_HZ if tabs <= CROWD else CROWD_HZ)
    if hz > MIN_HZ:
        assert tabs * hz * cost_ms / 1e3 <= SHARE * (1 + 1e-12)
    if tabs * (FRAME_HZ if tabs <= CROWD else CROWD_HZ) * cost_ms / 1e3 <= SHARE:
        assert hz == (FRAME_HZ if tabs <= CROWD else CROWD_HZ)  # a cheap frame: the rate is not cut


def test_the_running_mean_follows_a_change_of_cost_and_ignores_one_slow_frame():
    pace = _paced(1e-3)
    pace.spent(0.1)  # one frame 100 times dearer (a plot frame, a preset's first frame)
    assert pace.hz(10) > 0.5 * _paced(1e-3).hz(10)
    for _ in range(100):
        pace.spent(4e-3)
    assert pace.hz(10) == pytest.approx(SHARE / (10 * 4e-3), rel=1e-3)


def test_a_negative_or_zero_cost_does_not_divide_by_zero():
    pace = Pace()
    pace.spent(-1.0)
    assert pace.hz(10) == CROWD_HZ


def test_a_tabs_first_frame_which_draws_the_whole_scene_does_not_set_the_pace():
    pace = Pace()
    pace.spent(0.5)
    for _ in range(3):
        pace.spent(1e-3)
    assert pace.hz(10) == CROWD_HZ
