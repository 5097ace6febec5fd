"""A scene that explains itself (issue 13, point 6), headless: the legend lists exactly the parts the scene
draws; aligned arrows share one label; the e3 trail stays a trail at 10,000x; the moving mass is drawn on
the body at each scene's default exaggeration; the satellite mesh stays the body after a preset change."""

from __future__ import annotations

import contextlib
import math
import types
import warnings

import numpy as np
import pytest

import physics
from app.engine import presets
from app.engine.engine import Engine
from app.engine.geometry import rotate
from app.engine.trail import SAMPLES_PER_TURN, TRAIL_TURNS, largest_step, split_advance, turns_covered
from app.scene.labels import LABEL_GAP, label_groups
from app.scene.legend import entries, legend_markdown, parts_of
from physics.systems.moving_mass.figure import CAP_FRACTION, DRAWN_FRACTION, default_exaggeration, drawn_displacement

TRAIL_STEP_MAX = 2 * math.pi / SAMPLES_PER_TURN * (1 + 1e-6)  # rad: one chord spans at most 1/24 of a turn
DRAWN_LIMIT = 0.25  # the drawn displacement stays within this fraction of the body's size (DRAWN_FRACTION + dynamics)
WARP = 1e4  # the fastest warp the explorer offers
FRAME_S = 1 / 60  # wall seconds per frame


@pytest.fixture(autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", physics.ValidityWarning)
        yield


def _keys(sc, **kw) -> set[str]:
    return {e.key for e in entries(parts_of(sc, **kw))}


ALWAYS = {"K", "omega", "e3", "merged", "axes", "body", "ellipsoid", "trail"}
MASS = {"mass", "spring", "rest", "mount"}


def _preset_with(has) -> physics.Scenario:
    """The first preset whose scenario ``has`` (found by what it holds: other work renames the titles)."""
    for name in presets.preset_names():
        sc = presets.load_preset(name)
        if has(sc):
            return sc
    raise AssertionError("no preset has it")


def _braking(sc) -> bool:
    return sc.control is not None and sc.control.b > 0


@pytest.mark.parametrize("has, extra", [
    (lambda sc: sc.mass is not None and sc.cavity is None and not _braking(sc), MASS),
    (lambda sc: sc.mass is not None and sc.cavity is not None and _braking(sc), MASS | {"cavity", "torque"}),
    (lambda sc: sc.pendulum is not None, {"bob"}),
    (lambda sc: len(sc.plane_pendulums) == 3, {"bob"}),
    (lambda sc: sc.system == "moving_mass" and sc.mass is None, set()),
], ids=["mass", "mass-cavity-braking", "spherical-pendulum", "plane-pendulums", "bare-body"])
def test_the_legend_lists_exactly_the_parts_the_scene_has(has, extra):
    assert _keys(_preset_with(has)) == ALWAYS | extra


def test_the_legend_follows_the_view_the_polhode_the_mesh_and_the_factor():
    sc = physics.default_scenario()
    assert "polhode" in _keys(sc, polhode=True) and "polhode" not in _keys(sc)
    text = legend_markdown(parts_of(sc, exaggeration=20, mesh="satellite.stl", view="body"))
    assert "drawn x 20" in text and "satellite.stl" in text and "K's direction in the body" in text
    plane = _preset_with(lambda sc: len(sc.plane_pendulums) == 3)
    assert "bobs (3)" in legend_markdown(parts_of(plane))
    averaged = legend_markdown(parts_of(sc, state={}))
    assert "at rest" in averaged and "spring" not in averaged  # no displacement drawn, no factor claimed


def test_the_legend_is_one_block_of_lines_with_its_words_as_text_and_the_replay_shows_the_same_lines():
    from app.replay.page import legend_page_html
    from app.scene.legend import LEGEND_CLASS

    sc = physics.default_scenario()
    parts = parts_of(sc, mesh="<b>sat</b>&1.stl")
    text = legend_markdown(parts)
    assert text.startswith(f"<div class='{LEGEND_CLASS}' style=") and text.endswith("</div>") and "\n" not in text
    assert text.count("<br>") == len(entries(parts)) - 1  # one line per part
    assert "<b>" not in text and "&lt;b&gt;sat&lt;/b&gt;&amp;1.stl" in text  # a file's name is shown as written
    page = legend_page_html(text)
    assert page.count("<br>") == len(entries(parts)) - 1 and "<div" not in page and "<b>" not in page
    assert "&lt;b&gt;sat&lt;/b&gt;&amp;1.stl" in page and page.startswith("<span style='color:#")


def test_e3_is_called_the_symmetry_axis_only_on_a_symmetric_body():
    sc = physics.default_scenario()
    assert "e3: symmetry axis" in legend_markdown(parts_of(sc))
    lopsided = sc.with_values(**{"body.B": 1.05 * sc.body.A})
    text = legend_markdown(parts_of(lopsided))
    assert "symmetry axis" not in text and "e3: principal axis of C" in text


def test_a_stopped_braking_torque_leaves_the_legend():
    sc = _preset_with(_braking)
    assert "torque" in _keys(sc) and "torque" not in _keys(sc, braking=False)


SIZE = 1.5  # scene units the body spans (app.scene.drawing.SCENE_SIZE)


def _arrows(angle_deg: float) -> dict[str, np.ndarray]:
    """K, omega and e3 as the scene draws them (1.0, 0.9 and 0.9 body sizes), omega and e3 turned from K."""
    a = math.radians(angle_deg)
    return {"K": SIZE * np.array([0.0, 0.0, 1.0]),
            "omega": 0.9 * SIZE * np.array([math.sin(a / 2), 0.0, math.cos(a / 2)]),
            "e3": 0.9 * SIZE * np.array([math.sin(a), 0.0, math.cos(a)]),
            "torque": None}


def test_nearly_parallel_arrows_share_one_label():
    groups = label_groups(_arrows(2.0), SIZE)
    assert [g[0] for g in groups] == ["K, omega, e3"]
    np.testing.assert_allclose(groups[0][1], 1.08 * _arrows(2.0)["K"])  # at the longest arrow's tip


def test_arrows_far_apart_keep_their_own_labels():
    groups = label_groups(_arrows(40.0), SIZE)
    assert [g[0] for g in groups] == ["K", "omega", "e3"]
    anchors = np.array([g[1] for g in groups])
    gaps = [np.linalg.norm(anchors[i] - anchors[j]) for i in range(3) for j in range(i + 1, 3)]
    assert min(gaps) >= LABEL_GAP * SIZE  # none closer than the merging distance


def test_the_settled_default_scene_shows_one_label_for_k_omega_and_e3():
    e = Engine()
    for _ in range(20):  # 200 s: the nutation has closed (about 0.2 rad after a minute, then on towards 0)
        e._advance(10.0)
    fr = e.frame()
    k = SIZE / e.shape.extent
    groups = label_groups({"K": k * fr.K_vec, "omega": k * fr.omega_vec, "e3": k * fr.axis_vec, "torque": None},
                          SIZE)
    assert fr.theta < 0.05
    assert [g[0] for g in groups] == ["K, omega, e3"]


def _free_top() -> physics.Scenario:
    """The default body without its mass: nothing dissipates, so the cone keeps its 0.8 rad opening."""
    return physics.default_scenario().replace(mass=None)


def _trail_after(frames: int, warp: float, monkeypatch, split=True) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(trail points, K, the trail points' times, the cone's turn period) after ``frames`` frames at ``warp``.
    The times are read by wrapping the engine's trail feed (the trail itself keeps only points); the trail
    starts anew when it is cleared, as the engine does at high warp."""
    import app.engine.engine

    times: list[np.ndarray] = []
    feed = Engine._extend_trail
    e = Engine(_free_top())
    monkeypatch.setattr(e.trail, "clear", lambda clear=e.trail.clear: (times.clear(), clear()))

    def spy(self, tr):
        times.append(np.asarray(tr.t, dtype=float))
        feed(self, tr)

    monkeypatch.setattr(Engine, "_extend_trail", spy)
    if not split:
        monkeypatch.setattr(app.engine.engine, "split_advance", lambda dt, n, period: (dt, 0.0, 0))
    for _ in range(frames):
        e._advance(warp * FRAME_S)  # no wall-clock budget: each frame integrates warp / 60 simulated seconds
    fr = e.frame()
    t = np.concatenate(times)[-len(fr.trail):]
    return fr.trail, fr.K_vec, t, e.turn_period()


def test_the_trail_at_10000x_covers_its_last_few_turns_finely_sampled(monkeypatch):
    points, K, t, period = _trail_after(10, WARP, monkeypatch)
    assert len(points) > SAMPLES_PER_TURN and len(t) == len(points)  # there is a trail
    assert np.diff(t).max() <= period / SAMPLES_PER_TURN * (1 + 1e-9)  # consecutive points: 1/24 turn apart
    assert t[-1] - t[0] <= TRAIL_TURNS * period * (1 + 1e-9)  # a bounded number of turns: never a disc
    assert largest_step(points, K) <= TRAIL_STEP_MAX  # drawn, each chord spans 15 degrees of the circle
    assert turns_covered(points, K) <= TRAIL_TURNS + 1 / SAMPLES_PER_TURN


def test_without_the_dense_tail_the_trail_joins_points_many_turns_apart(monkeypatch):
    points, K, t, period = _trail_after(10, WARP, monkeypatch, split=False)
    assert np.diff(t).max() > 10 * period  # what the criterion above rules out: each chord skips ~20 turns


def test_at_1x_the_trail_is_the_continuous_history(monkeypatch):
    points, K, t, period = _trail_after(120, 1.0, monkeypatch)
    assert len(points) == 4 * 120 + 1  # every frame's samples (and the first point) are kept
    assert np.diff(t).max() <= period / SAMPLES_PER_TURN
    assert largest_step(points, K) <= TRAIL_STEP_MAX


def test_at_1x_the_trail_fills_its_ring_and_no_more():
    from app.engine.engine import TRAIL_POINTS

    e = Engine(_free_top())
    for _ in range(TRAIL_POINTS // 4 + 50):
        e._advance(FRAME_S)
    assert len(e.trail) == TRAIL_POINTS


def test_split_advance_keeps_the_frame_length():
    for dt in (0.01, 1.0, 166.7):
        head, tail, n = split_advance(dt, 4, 2.0)
        assert head + tail == pytest.approx(dt, rel=1e-12) and head >= 0 and tail >= 0
        if tail:
            assert tail / n <= 2.0 / SAMPLES_PER_TURN * (1 + 1e-12)


def _mass_presets() -> list[str]:
    return [n for n in presets.preset_names() if presets.load_preset(n).mass is not None]


@pytest.mark.parametrize("name", _mass_presets())
def test_the_mass_is_drawn_on_the_body_at_the_default_exaggeration(name):
    e = Engine(presets.load_preset(name))
    size = e.shape.extent
    worst = 0.0
    for _ in range(100):  # 10 s, several turns of the cone from the start, where |u| is largest
        e._advance(0.1)
        fr = e.frame()
        worst = max(worst, float(np.linalg.norm(np.subtract(fr.part("mass").centre, fr.part("rest").centre))) / size)
        assert "capped" not in fr.part("factor").text  # the default factor itself keeps it on the body, not the cap
    assert 1.0 <= e.exaggeration <= 1000.0
    assert worst <= DRAWN_LIMIT


def test_the_default_scene_no_longer_throws_the_mass_off_at_x10():
    e = Engine()
    u_scale = 0.412  # m: |omega|^2 rho / Omega^2 of the default scene (2.62^2 * 1.5 / 25)
    assert e.exaggeration * u_scale <= DRAWN_FRACTION * e.shape.extent * 1.01
    assert 10 * u_scale > 1.0 * e.shape.extent  # x10, as before, drew it more than a body's size away


def test_default_exaggeration_is_a_readable_number_within_the_slider():
    assert default_exaggeration(1.0, 1.5, 10.0, 1.0) == 10.0  # |u| ~ 0.015 m: 0.15 / 0.015 = 10 -> 10
    assert default_exaggeration(1.0, 1.5, 10.0, 1.2) == 5.0  # |u| ~ 0.0216 m: 6.9 -> 5
    assert default_exaggeration(3.35, 1.5, 5.0, 2.62) == 1.0  # want 1.2 -> 1
    assert default_exaggeration(1.0, 1e-9, 10.0, 1.0) == 1000.0  # capped at the slider's end
    assert default_exaggeration(1.0, 1.5, 10.0, 0.0) == 1.0  # nothing to draw


def test_a_large_factor_is_capped_and_says_so():
    d, capped = drawn_displacement(np.array([0.1, 0.0, 0.0]), 1000.0, 2.0)
    assert capped and np.linalg.norm(d) == pytest.approx(CAP_FRACTION * 2.0)
    np.testing.assert_allclose(d / np.linalg.norm(d), [1.0, 0.0, 0.0])  # the direction is kept
    d, capped = drawn_displacement(np.array([0.01, 0.0, 0.0]), 2.0, 2.0)
    assert not capped and d[0] == pytest.approx(0.02)


def test_the_chosen_satellite_stays_the_body_after_a_preset_change():
    e = Engine()
    e.request("mesh", "satellite.stl")
    e.tick(FRAME_S)
    assert e.mesh is not None and e.shape.kind == "mesh"
    e.request("preset", "Explorer 1's flat spin")
    e.tick(FRAME_S)
    assert e.error == ""
    assert e.mesh is not None and e.mesh.name == "satellite.stl" and e.shape.kind == "mesh"
    assert e.preset.startswith("Explorer 1's flat spin")
    flat = presets.load_preset("Explorer 1's flat spin").body
    b = e.scenario.body
    assert b.A + b.B + b.C == pytest.approx(flat.A + flat.B + flat.C, rel=1e-12)  # the mesh scaled to the preset
    assert e.scene_changed  # the drawing redraws the mesh
    assert "satellite.stl" in legend_markdown(parts_of(e.scenario, mesh=e.mesh.name))


def test_the_trail_point_is_the_tip_of_e3_in_the_view():
    e = Engine(_free_top())
    q = e.run.last.quat[0]
    np.testing.assert_allclose(e._trail_point(q), rotate(e.world_wxyz, rotate(q, [0.0, 0.0, 1.0])))


def test_the_legend_window_is_as_tall_as_its_lines_and_follows_them():
    """At a fixed LEGEND_BOX height the default scene's 14 lines left 59 px of empty window under them (measured
    in chromium). The window takes a row per line (two for a line too long for one), at most LEGEND_BOX's height,
    and is resized only when the lines change."""
    from app.scene.legend import LEGEND_BOX, LEGEND_CHARS, LEGEND_FRAME_PX, LEGEND_LINE_PX, LegendView, legend_height

    sc = physics.default_scenario()
    short, full = parts_of(sc), parts_of(sc, polhode=True)
    assert legend_height(full) == pytest.approx(legend_height(short) + LEGEND_LINE_PX)
    assert legend_height(short) == pytest.approx(LEGEND_FRAME_PX + len(entries(short)) * LEGEND_LINE_PX)
    assert legend_height(short) < LEGEND_BOX[3]
    long_name = "m" * (2 * LEGEND_CHARS) + ".stl"
    assert legend_height(parts_of(sc, mesh=long_name)) >= legend_height(short) + 2 * LEGEND_LINE_PX
    crowded = parts_of(sc, polhode=True, mesh=long_name * 3, second="m = 0 kg")
    assert legend_height(crowded) == LEGEND_BOX[3]  # beyond it the window scrolls

    class Window:
        def __init__(self):
            self.heights = []

        def add_tab(self, _):
            return contextlib.nullcontext()

        def float(self, **_):
            pass

        def set_height(self, h):
            self.heights.append(h)

    class Gui:
        def __init__(self):
            self.window = Window()

        def add_panel(self):
            return self.window

        def add_markdown(self, text):
            return types.SimpleNamespace(content=text)

    gui = Gui()
    view = LegendView(gui)
    view.show(short)
    view.show(short)  # the same lines: no resize (a user's own size stays)
    view.show(full)
    assert gui.window.heights == [legend_height(short), legend_height(full)]
