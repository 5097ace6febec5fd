"""The engine's whole-run plots, CSV export and overlay (app/engine/engine.py, app/engine/workers.py), headless: the
plots and the export cover the run from t = 0 however long it has played, in bounded memory, and the
cheaper model's prediction starts at t = 0 too."""

from __future__ import annotations

import io
import re

import numpy as np
import pytest
from fake_gui import FakeGui, chart_finite

import physics
from app.engine import engine as engine_module
from app.panel.plots import build_plots, update_plots
from app.state import FRAME_HZ, PLOT_POINTS, SAMPLES_PER_FRAME, Engine

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")
DT = 1.0 / FRAME_HZ


def ticks(e: Engine, n: int) -> None:
    for _ in range(n):
        e.tick(DT)


@pytest.fixture
def small_stores(monkeypatch):
    """Stores a long run overflows many times in a few hundred frames (the sizes are read at a restart)."""
    monkeypatch.setattr(engine_module, "HISTORY_ROWS", 64)
    monkeypatch.setattr(engine_module, "WHOLE_RUN_POINTS", 32)


def parse_csv(text: str) -> tuple[list[str], list[str], np.ndarray]:
    lines = text.splitlines()
    comments = [ln for ln in lines if ln.startswith("#")]
    columns = lines[len(comments)].split(",")
    table = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=len(comments) + 1, ndmin=2)
    return comments, columns, table


def test_plots_cover_the_whole_run_after_a_long_run(small_stores):
    e = Engine()
    e.request("warp", 100.0)
    frames = 400  # 1600 samples: the whole-run store of 32 halves about six times
    ticks(e, frames)
    t, theta, over, K, E = e.plot_data("whole")
    assert t[0] == 0.0 and t[-1] == e.run.t  # from t = 0 to now
    assert len(t) <= 32 + 1 and np.all(np.diff(t) > 0)
    assert e.plot_all.stride >= 32  # it was thinned, not truncated
    # every point is a sample of the run: the recent window's samples are among the whole run's
    recent = e.plot_data("recent")[0]
    assert len(recent) == min(PLOT_POINTS, 1 + frames * SAMPLES_PER_FRAME)
    common = np.intersect1d(t, recent)
    assert len(common) >= 1
    i, j = np.searchsorted(t, common[-1]), np.searchsorted(recent, common[-1])
    assert theta[i] == e.plot_data("recent")[1][j]


def test_the_panel_chooses_what_the_plots_show():
    e = Engine()
    ticks(e, PLOT_POINTS // SAMPLES_PER_FRAME + 10)
    assert e.plot_data()[0][0] == 0.0  # the whole run by default
    e.request("plots", "recent")
    ticks(e, 1)
    assert e.plot_span == "recent" and e.plot_data()[0][0] > 0.0
    e.request("plots", "everything")
    ticks(e, 1)
    assert "plots show 'everything'" in e.error and e.plot_span == "recent"


def test_csv_starts_at_t0_and_says_it_was_thinned(small_stores):
    e = Engine()
    e.request("warp", 100.0)
    ticks(e, 300)
    comments, columns, table = parse_csv(e.csv().decode())
    assert columns[:4] == ["t", "theta", "K", "E"] and table.shape[1] == len(columns)
    assert table[0, 0] == 0.0 and table[-1, 0] == pytest.approx(e.run.t, rel=1e-15)
    assert len(table) <= 64 + 1
    stride = e.history.stride
    m = re.search(r"rows decimated: every (\d+)(?:st|nd|rd|th) sample kept", comments[0])
    assert stride > 1 and m and int(m.group(1)) == stride
    # the rows are the run's samples, every stride-th: the plots' whole-run rows (a coarser stride of the
    # same samples) are rows of the export, value for value
    t_plot, theta_plot = e.plot_data("whole")[:2]
    rows = {float(r[0]): r for r in table}
    shared = [k for k, tp in enumerate(t_plot) if float(tp) in rows]
    assert len(shared) >= 2
    for k in shared:
        assert rows[float(t_plot[k])][1] == theta_plot[k]


def test_csv_names_the_edits_the_run_went_through():
    e = Engine()
    ticks(e, 5)
    e.request_value("mass.m", 0.15)
    ticks(e, 5)
    comments, columns, table = parse_csv(e.csv().decode())
    assert table[0, 0] == 0.0 and "every sample kept" in comments[0]
    assert len(comments) == 2 and comments[1].startswith("# edited since t = 0 (t = ")
    e.request("reset")
    ticks(e, 1)
    comments, _, _ = parse_csv(e.csv().decode())
    assert len(comments) == 1  # a reset starts a run of the edited scene: nothing to report


def test_overlay_starts_at_t0_and_follows_a_long_run():
    e = Engine()
    e.request("overlay", "averaged")
    ticks(e, 2)
    assert e.wait_overlay()
    first_end = e.overlay[0][-1]
    e.request("warp", 100.0)
    ticks(e, 60)  # past the first prediction's end: predicted again, from t = 0 still
    e.wait_overlay()
    ticks(e, 1)
    e.wait_overlay()
    ot, oth = e.overlay
    assert ot[0] == 0.0 and ot[-1] > first_end and ot[-1] >= e.run.t
    ref = physics.simulate(e.scenario.with_values(**{"run.t_end": float(ot[-1]), "run.samples": 5}),
                           fidelity="averaged")
    np.testing.assert_allclose(np.interp(ref.t, ot, oth), ref.theta, atol=1e-6)  # rad
    assert e.overlay_title() == "theta and the averaged model's prediction from t = 0"


def test_overlay_after_an_edit_is_of_the_scene_at_t0_and_says_so():
    e = Engine()
    e.request("overlay", "averaged")
    ticks(e, 2)
    assert e.wait_overlay()
    before = e.overlay
    e.request_value("mass.chi", 12.0)
    ticks(e, 2)
    e.wait_overlay()
    assert e.overlay[0][0] == 0.0
    np.testing.assert_array_equal(e.overlay[1], before[1])  # the prediction of the run's start
    assert "for the scene at t = 0 (edited since: " in e.overlay_title()


@pytest.mark.parametrize("system", ["plane_pendulums", "wheel", "spherical_pendulum"])
def test_a_subnormal_nutation_is_charted_without_raising(system):
    """theta0 = 1e-320 on these systems gives a theta series of subnormal values; the charts' scale took
    10.0**-324 == 0.0 for its power of ten and raised ZeroDivisionError in the tab's loop (found by replaying the
    websocket storm's values through the engine, slider by slider, on every system). The real engine, the real
    charts on a fake gui: every plotted number and every axis end finite."""
    e = Engine()
    e.request("system", system)
    ticks(e, 1)
    e.request_value("initial.theta0", 1e-320)
    ticks(e, 1)
    assert e.scenario.system == system and e.scenario.initial.theta0 == 1e-320
    gui = FakeGui()
    charts = build_plots(gui, e.plot_data())
    for _ in range(6):
        ticks(e, 1)
        update_plots(charts, e.plot_data())
    theta = e.plot_data()[1]
    assert 0 < np.max(np.abs(theta)) < 1e-300  # the case: a subnormal series that varies
    for h in (h for h in gui.handles if h.kind == "uplot" and h.visible):
        assert h.scales is not None and "y" in h.scales, h.title  # the axis was set from the data
        assert chart_finite(h), (h.title, h.scales)


def test_a_scene_that_stops_at_its_start_replaces_the_last_scenes_curves():
    """A shared scene whose run faults at t = 0 (body.C = 1e-8 beside A = B = 1) has one row to plot. The charts,
    which draw nothing of fewer than two points, kept the previous scene's curves under the new scene's readouts;
    now they show its start."""
    e = Engine()
    gui = FakeGui()
    charts = build_plots(gui, e.plot_data())
    ticks(e, 30)
    update_plots(charts, e.plot_data())
    theta_chart = next(h for h in gui.handles if h.kind == "uplot" and h.title == "nutation angle theta")
    assert len(theta_chart.data[0]) > 2
    e.request("scenario", (e.scenario.with_values(**{"body.C": 1e-8}), "shared scene"))
    ticks(e, 3)
    assert e.run.status == "fault" and "body.C = 1e-08" in e.run.message
    t, theta, _, K, E = e.plot_data()
    assert list(t) == [0.0, 0.0] and theta[0] == theta[1] == e.run.last.theta[0]
    update_plots(charts, e.plot_data())
    assert list(theta_chart.data[0]) == [0.0, 0.0]  # the new scene's start, not the last scene's curve
    assert chart_finite(theta_chart)
