"""The sweep panel's numbers: ranges that keep the precision typed, default ranges valid at every point for
every preset, failed points that say why, a "best" that leaves out growing points, an outlier-proof colour
scale, and results marked stale when the scene changes (issue 13, point 3)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import physics

pytest.importorskip("plotly")
from fake_gui import FakeGui  # noqa: E402

from app.engine import presets  # noqa: E402
from app.engine.controls import BY_KEY  # noqa: E402
from app.studies import sweep_ranges, sweep_view
from app.studies.slider_choice import sweepable  # noqa: E402
from app.studies.speed_panel import SpeedPanel  # noqa: E402
from app.studies.sweep_panel import SweepPanel  # noqa: E402


def named(key: str) -> str:
    """The text a parameter dropdown offers for the slider ``key`` (its label and unit, as the slider reads)."""
    return BY_KEY[key].text


def _table(keys, axes, values, metric="decay_time", errors=None, base=None):
    """A SweepTable with given metric values (grid order), built without running anything."""
    base = base or physics.default_scenario()
    rows = []
    import itertools

    for i, point in enumerate(itertools.product(*axes)):
        row = dict(zip(keys, point, strict=True))
        row[metric] = float(values[i])
        row["model"], row["error"] = "", (errors or {}).get(i, "")
        rows.append(row)
    return physics.SweepTable(base=base, keys=tuple(keys), axes=tuple(tuple(a) for a in axes),
                              spacing=("linear",) * len(keys), metrics=(metric,), metric=metric, rows=rows)


# ---- ranges ---------------------------------------------------------------------------------------

def test_typed_ranges_keep_their_precision_and_the_run_covers_them():
    sc = physics.default_scenario()
    panel = SweepPanel(FakeGui(), lambda: sc, lambda s: None, executor="serial")
    panel.key1.value = named("mass.m")
    panel.key1.fire()
    assert panel.lo1.precision >= sweep_ranges.BOX_DIGITS  # the browser's box keeps the typed decimals
    panel.lo1.value, panel.hi1.value, panel.n1.value = 0.05, 0.25, 5
    _, vary, _ = panel.request()
    values, _ = physics.axis_values(vary["mass.m"])
    assert values[0] == 0.05 and values[-1] == 0.25 and len(values) == 5
    assert sweep_ranges.box_precision(0.0001234) >= 7  # finer values widen the box further


def test_default_m_range_of_the_default_scene_stops_below_the_invalid_masses():
    sc = physics.default_scenario()
    lo, hi = sweep_ranges.wanted_range(sc, "mass.m")
    bad = sweep_ranges.invalid_points(sc, "mass.m", lo, hi, 8)
    assert bad, "the old default range (value/2 .. 2 value) had invalid points: the test needs one that fails"
    a, b = sweep_ranges.default_range(sc, "mass.m", 8)
    assert a == pytest.approx(lo) and b < hi
    assert sweep_ranges.invalid_points(sc, "mass.m", a, b, 8) == []
    assert sweep_ranges.point_error(sc, "mass.m", 1.05 * b) or b > 0.9 * min(v for v, _ in bad)


PRESETS = presets.preset_names()
ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("name", PRESETS)
def test_every_default_range_of_every_preset_is_valid_at_every_point(name):
    sc = presets.load_preset(name)
    for key in sweepable(sc):
        lo, hi = sweep_ranges.default_range(sc, key, 8)
        assert lo < hi, (key, lo, hi)
        if sweep_ranges.point_error(sc, key, sweep_ranges.current_value(sc, key)):
            continue  # a slider at 0 that removes its part: no valid anchor to build a range on
        assert sweep_ranges.invalid_points(sc, key, lo, hi, 8) == [], (name, key, lo, hi)


# ---- failed points and "best" -------------------------------------------------------------------

def test_a_failed_point_says_which_key_value_and_range():
    sc = physics.default_scenario()
    gui = FakeGui()
    panel = SweepPanel(gui, lambda: sc, lambda s: None, executor="serial")
    panel.key1.value = named("mass.m")
    panel.lo1.value, panel.hi1.value, panel.n1.value = 0.3, 0.45, 2  # 0.45: m rho^2/(1 - m/M) exceeds A
    panel.metric.value = "theta_end"
    sc = sc.with_values(**{"run.t_end": 2.0, "run.samples": 21})
    panel.get_scenario = lambda: sc
    panel.start().join(timeout=120)
    failed = [label for label in panel._points if "failed" in label]
    assert len(failed) == 1
    assert "mass.rho = 1.5" in failed[0] and "must be less than A and B" in failed[0]
    assert failed[0] != "ScenarioError" and "ScenarioError" not in failed[0]
    assert "must be less than A and B" in panel.result_md.content and "1 point(s) failed" in panel.result_md.content
    assert panel.load_point(1) is None and "cannot be loaded" in panel.status.content


def test_best_decay_time_is_the_fastest_decay_not_a_growing_point():
    values = [-106.0, 40.0, 12.0, math.inf, 300.0, -5.0]
    table = _table(["mass.Omega", "mass.chi"], [[2.5, 30.0], [1.0, 10.0, 30.0]], values)
    b = sweep_view.best(table)
    assert b == 2 and table.rows[b]["decay_time"] == 12.0
    order = sweep_view.ranked(table)
    assert order[:3] == [2, 1, 4]  # decaying points, fastest first; growing and flat ones after
    text = sweep_view.summary(table)
    assert "decay_time = 12 s" in text and "tau < 0 grows" in text and "2 point(s) where the nutation grows" in text
    assert "-106" not in text.split("  \n")[0]
    assert any("(grows)" in sweep_view.point_label(table, i) for i in (0, 5))


def test_no_decaying_point_means_no_best():
    table = _table(["mass.chi"], [[1.0, 2.0]], [-3.0, -7.0])
    assert sweep_view.best(table) is None and "none of the points qualifies" in sweep_view.summary(table)


def test_energy_dissipated_prefers_the_largest():
    table = _table(["mass.chi"], [[1.0, 2.0, 3.0]], [0.5, 2.0, 1.0], metric="energy_dissipated")
    assert sweep_view.best(table) == 1


# ---- colour scale ---------------------------------------------------------------------------------

def test_one_huge_cell_gets_a_log_scale_so_the_others_stay_distinguishable():
    values = [30.0, 40.0, 50.0, 60.0, 250_000.0, 45.0]
    scale = sweep_view.colour_scale(values, "s")
    assert scale.kind == "log" and "log" in scale.title
    mapped = [scale.apply(v) for v in values]
    spread_others = (max(mapped[:4]) - min(mapped[:4])) / (max(mapped) - min(mapped))
    linear_spread = (60.0 - 30.0) / (250_000.0 - 30.0)
    assert spread_others > 100 * linear_spread
    fig = sweep_view.figure(_table(["mass.Omega", "mass.chi"], [[1.0, 2.0], [1.0, 2.0, 3.0]], values,
                                   metric="braking_time"))
    assert "log" in fig.data[0].colorbar.title.text and fig.data[0].colorbar.ticktext


def test_decay_time_heat_map_is_coloured_by_the_rate_growth_below_zero():
    values = [-106.0, 40.0, 12.0, 250_000.0, 30.0, 20.0]
    fig = sweep_view.figure(_table(["mass.Omega", "mass.chi"], [[2.5, 30.0], [1.0, 10.0, 30.0]], values))
    heat = fig.data[0]
    z = [c for row in heat.z for c in row]
    assert z[0] < 0 < z[3] < min(z[1], z[2], z[4], z[5])  # growing below 0; the near-flat cell just above 0
    assert z[2] > z[5] > z[4] > z[1]  # faster decay, larger rate: the decaying cells keep their order
    assert heat.zmid == 0 and "1/tau" in heat.colorbar.title.text and "red grows" in fig.layout.title.text
    blue, red = (lambda c: c[2] > c[0]), (lambda c: c[0] > c[2])
    assert red(_cell_colour(heat, z[0])) and all(blue(_cell_colour(heat, v)) for v in z[1:])
    assert "decay_time = 2.5e+05 s" in heat.text[1][0]  # the hover still gives tau itself


def _rgb(text: str) -> tuple[float, ...]:
    return tuple(float(x) for x in text.strip("rgb() ").split(","))


def _cell_colour(heat, z: float) -> tuple[float, ...]:
    """The colour plotly draws a heat map's cell of value ``z`` in: its colour scale at z's place between the
    bounds (symmetric about zmid when one is set), interpolated linearly."""
    zs = [c for row in heat.z for c in row if c is not None]
    lo, hi = min(zs), max(zs)
    if heat.zmid is not None:
        half = max(abs(lo - heat.zmid), abs(hi - heat.zmid))
        lo, hi = heat.zmid - half, heat.zmid + half
    t = 0.5 if hi == lo else (z - lo) / (hi - lo)
    stops = [(float(p), _rgb(c)) for p, c in heat.colorscale]
    for (p0, c0), (p1, c1) in zip(stops, stops[1:], strict=False):
        if p0 <= t <= p1:
            f = (t - p0) / (p1 - p0)
            return tuple(a + f * (b - a) for a, b in zip(c0, c1, strict=True))
    raise AssertionError(t)


def test_a_heat_map_where_every_point_decays_is_blue_and_says_so():
    """Issue 24: decay times of 15 to 2577 s (a rate span beyond LOG_SPAN, so log colours) were all drawn red
    under "blue decays, red grows": the log of a rate below 1 is negative, and the scale was centred on 0."""
    values = list(np.geomspace(15.0, 2577.0, 20))
    fig = sweep_view.figure(_table(["mass.Omega", "mass.chi"], [list(range(1, 5)), list(range(1, 6))], values))
    heat = fig.data[0]
    z = [c for row in heat.z for c in row]
    colours = [_cell_colour(heat, v) for v in z]
    assert all(c[2] > c[0] for c in colours)  # every cell blue, not red
    fastest, slowest = colours[0], colours[-1]
    assert sum(fastest) < sum(slowest)  # the fastest decay (tau = 15 s) darkest
    assert "every point decays" in fig.layout.title.text and "red" not in fig.layout.title.text


def test_a_heat_map_where_every_point_grows_is_red_and_says_so():
    values = [-10.0, -20.0, -40.0, -80.0, -160.0, -320.0]
    heat_fig = sweep_view.figure(_table(["mass.Omega", "mass.chi"], [[1.0, 2.0], [1.0, 2.0, 3.0]], values))
    heat = heat_fig.data[0]
    colours = [_cell_colour(heat, v) for row in heat.z for v in row]
    assert all(c[0] > c[2] for c in colours) and sum(colours[0]) < sum(colours[-1])  # fastest growth darkest
    assert "every point grows" in heat_fig.layout.title.text


def test_mixed_sign_outlier_is_clipped_and_the_scale_says_so():
    values = [-106.0, 30.0, 32.0, 35.0, 31.0, 33.0, 34.0, 36.0]
    scale = sweep_view.colour_scale(values, "s")
    assert scale.kind == "clipped" and "clipped" in scale.title
    assert scale.lo > -106.0 and scale.apply(-106.0) == scale.lo
    assert scale.apply(33.0) == 33.0
    assert sweep_view.colour_scale([1.0, 2.0, 3.0], "s").kind == "linear"


# ---- stale results ------------------------------------------------------------------------------

def test_sweep_result_is_marked_stale_when_the_scene_changes_but_not_when_a_point_is_loaded():
    scenes = [physics.default_scenario()]
    panel = SweepPanel(FakeGui(), lambda: scenes[-1], scenes.append, executor="serial")
    table = _table(["mass.chi"], [[2.0, 4.0, 8.0]], [30.0, 20.0, 25.0], base=scenes[0])
    panel.show(table)
    assert "Stale" not in panel.result_md.content
    panel.load_point(1)  # the scene becomes one of the sweep's points
    panel.scene_changed()
    assert not panel.stale and "STALE" not in panel.plot.figure.layout.title.text
    scenes.append(physics.point_scenario(scenes[0], {"mass.m": 0.1}))  # another slider moved
    panel.scene_changed()
    assert panel.stale and "Stale" in panel.result_md.content and "STALE" in panel.plot.figure.layout.title.text
    scenes.append(scenes[0])
    panel.scene_changed()
    assert not panel.stale and "Stale" not in panel.result_md.content


def _fake_work_precision(sc, progress=None, cancel=None):
    """A stand-in physics.work_precision with one recommended row (the real one is tested elsewhere)."""
    row = physics.WorkPrecisionRow(method="RK4", setting=0.01, error=1e-8, wall_s=0.01, nfev=400, steps=100)
    return physics.WorkPrecision(fidelity="full", model=f"{sc.system}/full", horizon=1.0, tolerance=1e-6,
                                 tolerance_source="test", rows=[row], recommended=row)


def test_speed_result_goes_stale_after_a_scene_change_and_cannot_be_applied():
    scenes = [physics.default_scenario()]
    applied = []
    panel = SpeedPanel(FakeGui(), lambda: scenes[-1], applied.append, sweep=_fake_work_precision)
    panel.start().join(30)
    assert panel.result is not None and not panel.use_btn.disabled
    scenes.append(panel.result.apply(scenes[0]))  # applying the recommendation changes only the method
    panel.scene_changed()
    assert not panel.stale
    scenes.append(physics.point_scenario(scenes[0], {"mass.chi": 9.0}))
    panel.scene_changed()
    assert panel.stale and panel.use_btn.disabled and "Stale" in panel.status.content
    assert panel.use_recommended() is None and applied == []
    assert "STALE" in panel.plot.figure.layout.title.text


def test_speed_chart_leaves_room_legend_below_no_toolbar():
    result = _fake_work_precision(physics.default_scenario())
    from app.studies.speed_panel import figure

    fig = figure(result)
    legend = fig.layout.legend
    # at the figure's foot, whatever the plot's height, below the tick labels and axis title the margin holds
    assert legend.orientation == "h" and legend.yref == "container" and legend.y == 0 and legend.yanchor == "bottom"
    assert fig.layout.margin.b >= 100
    assert fig.layout.xaxis.dtick == 1  # one tick a decade
    label = next(a for a in fig.layout.annotations if a.text == "requested")
    assert label.y == pytest.approx(math.log10(result.tolerance))  # on the dashed line (log axis: the exponent)
    gui = FakeGui()
    SpeedPanel(gui, physics.default_scenario, lambda s: None, sweep=_fake_work_precision)
    plot = next(h for h in gui.handles if h.kind == "plotly")
    assert plot.kw["config"] == {"displayModeBar": False}


def test_sweep_board_is_opt_in_and_placed_in_front_of_the_body():
    from app.studies import sweep_board

    corner = np.array(sweep_board.BOARD_AT[:2])
    far = corner + sweep_board.BOARD_SIZE
    camera_right = np.array([3.4, 3.0]) / np.hypot(3.4, 3.0)  # the default camera's screen-right on the floor
    assert float(camera_right @ ((corner + far) / 2)) < 0.5  # not off to the right, behind the control panel


def test_check_point_raises_what_the_point_s_run_would():
    sc = physics.default_scenario()
    with pytest.raises(physics.ScenarioError, match="must be less than A and B"):
        physics.check_point(sc, {"mass.m": 0.4})
    ok = physics.check_point(sc, {"mass.m": 0.3})
    assert ok.to_dict() == physics.point_scenario(sc, {"mass.m": 0.3}).to_dict()


def test_board_cells_colour_growth_red_and_the_fastest_decay_darkest():
    from app.studies.sweep_board import board_cells

    values = [-106.0, 40.0, 12.0, 250_000.0, 30.0, 20.0]
    cells = board_cells(_table(["mass.Omega", "mass.chi"], [[2.5, 30.0], [1.0, 10.0, 30.0]], values))
    colour = {i: c for i, _, c, _ in cells}
    assert colour[0][0] > colour[0][2]  # growth: red over blue
    assert all(colour[i][2] >= colour[i][0] for i in (1, 2, 3, 4, 5))  # decay: blue over red
    assert min(colour, key=lambda i: sum(colour[i])) == 2  # the fastest decay (tau = 12 s) is darkest


def test_a_scene_change_during_the_sweep_marks_the_result_stale_on_arrival():
    scenes = [physics.default_scenario().with_values(**{"run.t_end": 2.0, "run.samples": 21})]
    panel = SweepPanel(FakeGui(), lambda: scenes[-1], lambda s: None, executor="serial")
    panel.key1.value = named("mass.chi")
    panel.lo1.value, panel.hi1.value, panel.n1.value = 2.0, 4.0, 2
    sc, vary, metric = panel.request()
    scenes.append(physics.point_scenario(scenes[0], {"mass.m": 0.1}))  # moved while the sweep ran
    panel.work(sc, vary, metric)
    assert panel.table is not None and panel.stale and "Stale" in panel.result_md.content


def test_the_chart_names_its_axes_as_the_sliders_read_with_their_units():
    """The axes said the scenario key ("mass.chi"), without a unit; they now say the slider's text, and a key no
    slider sets (a sweep from a file may vary any numeric key) keeps its name."""
    heat = sweep_view.figure(_table(["mass.Omega", "mass.chi"], [[2.5, 30.0], [1.0, 10.0, 30.0]], [1.0] * 6))
    assert heat.layout.yaxis.title.text == named("mass.Omega") == "Omega (rad/s)"
    assert heat.layout.xaxis.title.text == named("mass.chi") and "chi (1/s) = " in heat.data[0].hovertemplate
    curve = sweep_view.figure(_table(["run.t_end"], [[1.0, 2.0]], [1.0, 2.0]))
    assert curve.layout.xaxis.title.text == "run.t_end"
    plane = physics.Scenario.load(ROOT / "assets" / "scenarios" / "plane_pendulums_three.toml")
    bobs = sweep_view.figure(_table(["plane_pendulum.k"], [[1.0, 2.0]], [1.0, 2.0], base=plane))
    assert bobs.layout.xaxis.title.text == named("pendulum.k")
