"""Headless checks of one tab's simulation state (app/state.py, app/engine/controls.py, app/engine/presets.py):
changes go through physics, bad input is rejected with the state kept, buffers stay bounded."""

from __future__ import annotations

import io
import math
import time

import numpy as np
import pytest

import physics
from app.__main__ import parse
from app.engine import controls, presets
from app.engine.engine import WHOLE_RUN_POINTS
from app.state import FRAME_HZ, PLOT_POINTS, SAMPLES_PER_FRAME, TRAIL_POINTS, Engine

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")
DT = 1.0 / FRAME_HZ
ANGLE_TOL = 1e-9  # rad


def ticks(engine: Engine, n: int):
    fr = None
    for _ in range(n):
        fr = engine.tick(DT)
    return fr


def test_default_engine_plays_with_K_up():
    # the clock integrates what the last tick's measured rate affords: a first tick that loads the compiled
    # kernels into this process (about a second, when no earlier test has) would cut the second tick short,
    # so they are loaded first, as a server does before its first page (app.serve.server.warm_up)
    physics.LiveRun(physics.default_scenario()).advance(0.01)
    e = Engine()
    assert e.preset == presets.DEFAULT and e.run.fidelity == "full"
    fr = ticks(e, 10)
    assert fr.t == pytest.approx(10 * DT * e.warp)
    for v in (fr.K_vec, fr.omega_vec, fr.axis_vec, fr.body_wxyz, fr.part("mass").centre):
        assert np.all(np.isfinite(v))
    K = fr.K_vec / np.linalg.norm(fr.K_vec)
    np.testing.assert_allclose(K, [0, 0, 1], atol=1e-9)  # the inertial view puts the fixed K up
    assert fr.torque_vec is None
    assert len(fr.trail) == 1 + 10 * SAMPLES_PER_FRAME
    np.testing.assert_allclose(fr.trail[-1], fr.axis_vec, atol=1e-12)  # the e3 arrow's tip draws the trail


def test_a_slider_change_keeps_the_state_and_acts():
    e = Engine()
    ticks(e, 5)
    t, y = e.run.t, e.run.y.copy()
    seq = e.request_value("mass.chi", 2.0)
    fr = e.tick(0.0)
    assert fr.applied >= seq and e.error == ""
    assert e.run.t == t and np.array_equal(e.run.y, y)
    assert e.scenario.mass.chi == 2.0


def test_bad_input_is_rejected_and_the_last_good_state_stays():
    e = Engine()
    ticks(e, 3)
    good = e.scenario
    e.request_value("mass.m", 5.0)  # m >= M
    fr = e.tick(DT)
    assert "mass.m" in e.error and "less than body.M" in e.error
    assert e.scenario is good and fr.status == "running" and fr.t > 0
    e.request_value("mass.m", 0.2)
    e.tick(DT)
    assert e.error == "" and e.scenario.mass.m == 0.2


def test_initial_changes_and_restart_on_change_restart():
    e = Engine()
    ticks(e, 3)
    e.request_value("initial.theta0", 0.3)
    e.tick(0.0)
    # theta is K's angle; at the default's eps the mass's momentum tilts K from J* w by a few 0.01 rad
    fresh = physics.simulate(e.scenario.replace(run=physics.Run(t_end=1.0, samples=2, fidelity="full")))
    assert e.scenario.initial.theta0 == 0.3
    assert e.run.t == 0.0 and e.run.last.theta[0] == pytest.approx(fresh.theta[0], abs=1e-12)
    ticks(e, 3)
    e.request("restart_on_change", True)
    e.request_value("mass.chi", 3.0)
    e.tick(0.0)
    assert e.run.t == 0.0


def test_b_sets_the_braking_time_and_the_torque():
    e = Engine()
    assert e.readouts()["T"] == "no braking"
    e.request_value("control.b", 0.01)
    fr = e.tick(DT)
    remaining = e.run.remaining_braking_time()  # from the present |K|: T = t + remaining (app.engine.words)
    assert e.readouts()["T"] == f"{e.run.t + remaining:.6g} s" and math.isfinite(remaining)
    assert fr.torque_vec is not None and fr.torque_vec[2] < 0  # against K, which points up
    e.request_value("control.b", 0.0)
    e.tick(DT)
    assert e.scenario.control is None


def test_playback_actions():
    e = Engine()
    e.request("pause")
    ticks(e, 3)
    assert e.run.t == 0.0
    e.request("step")
    e.tick(DT)
    assert e.run.t == pytest.approx(e.warp / FRAME_HZ)
    e.request("warp", 1e9)
    e.tick(DT)
    assert e.warp == presets.WARP_MAX
    e.request("reset")
    e.request("play")
    e.tick(0.0)
    assert e.playing and e.run.t == 0.0


@pytest.mark.parametrize("name", presets.preset_names())
def test_every_preset_loads_and_runs(name):
    e = Engine()
    e.request("preset", name)
    fr = ticks(e, 3)
    assert e.error == "" and e.preset == name
    assert fr.t > 0 and np.isfinite(fr.theta)
    sc = e.scenario
    if sc.pendulum is not None or sc.plane_pendulums:
        assert len(fr.parts("bob")) == max(1, len(sc.plane_pendulums))
    assert e.readouts()["fidelity"].startswith(e.run.fidelity)
    badge = e.badge(block=True)  # auto's choice, or beside the scene's own: what auto would run
    chosen = sc.run.fidelity
    head = "**auto → " if chosen == "auto" else f"**{chosen}** as chosen; auto would run **"
    assert badge.startswith(head), badge


def test_the_presets_the_issue_asks_for():
    names = " ".join(presets.preset_names()).lower()
    for word in ("default", "oblate", "flat spin", "cavity and a resisting medium", "braking", "resonance", "detuned",
                 "plane pendulums", "intermediate-axis"):
        assert word in names, word


def test_system_fidelity_and_tune():
    e = Engine()
    e.request("system", "spherical_pendulum")
    e.tick(DT)
    assert e.scenario.system == "spherical_pendulum" and e.error == ""
    e.request("tune")
    e.tick(DT)
    assert e.scenario.pendulum.k == "resonant" and e.error == ""
    e.request("system", "moving_mass")
    e.request("fidelity", "averaged")
    e.tick(DT)
    # the state is carried (tests/test_app_edits.py), and the first frame after a change plays at least real time
    assert e.run.fidelity == "averaged" and DT * (1 - 1e-9) <= e.run.t <= e.warp * DT * (1 + 1e-9)


def test_body_view_holds_the_body_still():
    e = Engine()
    e.request("view", "body")
    fr = ticks(e, 5)
    np.testing.assert_array_equal(fr.body_wxyz, [1, 0, 0, 0])
    np.testing.assert_allclose(fr.axis_vec / np.linalg.norm(fr.axis_vec), [0, 0, 1], atol=ANGLE_TOL)


def test_buffers_stay_bounded():
    e = Engine()
    e.request("warp", 1000.0)
    ticks(e, (PLOT_POINTS + TRAIL_POINTS) // 4 + 50)
    # at 1000x the trail is the cone's last turns alone (app.engine.trail); it fills at 1x
    # (tests/test_app_scene_explains.py::test_at_1x_the_trail_fills_its_ring_and_no_more)
    assert len(e.plot) == PLOT_POINTS and 0 < len(e.trail) <= TRAIL_POINTS
    t, theta, over, K, E = e.plot_data("recent")
    assert len(t) == PLOT_POINTS and np.all(np.diff(t) > 0)
    t, theta, over, K, E = e.plot_data("whole")  # the whole run, thinned (tests/test_app_plots_engine.py)
    assert len(t) <= WHOLE_RUN_POINTS + 1 and t[0] == 0.0 and np.all(np.diff(t) > 0)


def test_overlay_prediction_is_the_cheaper_model_from_t0():
    e = Engine()
    e.request("overlay", "averaged")
    ticks(e, 2)
    assert e.wait_overlay()
    ticks(e, 20)
    t, theta, over, K, E = e.plot_data()
    assert e.has_overlay and np.all(np.isfinite(over)) and np.any(over != theta)
    ot, oth = e.overlay
    assert ot[0] == 0.0 and t[0] == 0.0  # on the same axes as the run, from its start
    ref = physics.simulate(e.start_scenario.with_values(**{"run.t_end": float(t[-1]), "run.samples": 7}),
                           fidelity="averaged")
    np.testing.assert_allclose(np.interp(ref.t, t, over), ref.theta, atol=1e-6)  # rad


def test_exports_round_trip():
    e = Engine()
    ticks(e, 5)
    sc = physics.Scenario.from_toml(e.toml().decode())
    assert sc == e.scenario
    lines = e.csv().decode().splitlines()
    assert lines[0].startswith("# ") and "every sample kept" in lines[0]  # what the rows are, then the columns
    table = np.loadtxt(io.StringIO(e.csv().decode()), delimiter=",", skiprows=2)
    header = lines[1].split(",")
    assert header[:4] == ["t", "theta", "K", "E"] and table.shape == (21, len(header))


def test_apply_changes_switches_parts_on_and_off():
    base = physics.default_scenario()
    sc = controls.apply_changes(base, {"medium.lambda": 0.001, "control.b": 0.01, "cavity.beta": 500.0})
    assert sc.medium.lambda_ == 0.001 and sc.control.b == 0.01 and sc.cavity.beta == 500.0
    sc = controls.apply_changes(sc, {"medium.lambda": 0.0, "control.b": 0.0, "cavity.beta": 0.0})
    assert sc.medium is None and sc.control is None and sc.cavity is None
    assert controls.apply_changes(base, {"mass.m": 0.0}).mass is None
    with pytest.raises(physics.ScenarioError):
        controls.apply_changes(base, {"no.such": 1.0})
    assert controls.values_of(base)["mass.chi"] == base.mass.chi
    assert set(controls.SIX) <= set(controls.BY_KEY)


def test_cli_defaults():
    a = parse([])
    assert (a.host, a.port, a.scenario) == ("127.0.0.1", 8080, None)
    assert parse(["--port", "0", "--scenario", "x.toml"]).port == 0


def test_server_starts_on_a_free_port_and_stops():
    from app.serve.server import App

    app = App(port=0)
    try:
        assert app.port > 0
    finally:
        app.close()


def test_cli_rejects_a_bad_scenario_file(tmp_path, capsys):
    from app.__main__ import main

    bad = tmp_path / "bad.toml"
    bad.write_text("[body]\nA = -1.0\nC = 1.0\nM = 1.0\n[initial]\nG0 = 1.0\ntheta0 = 0.1\n[run]\nt_end = 1.0\n")
    assert main(["--scenario", str(bad), "--port", "0"]) == 2
    assert "body.A" in capsys.readouterr().err
    assert main(["--scenario", str(tmp_path / "missing.toml"), "--port", "0"]) == 2


def test_tune_to_resonance_shows_the_resolved_k_on_its_slider():
    e = Engine(preset="Spherical pendulum damper, detuned")
    assert e.values["pendulum.k"] == 0.05
    e.request("tune")
    e.tick(DT)
    k = physics.derived(e.scenario)["k"]
    assert e.error == "" and e.scenario.pendulum.k == "resonant"
    assert e.values["pendulum.k"] == pytest.approx(k, rel=1e-12) and abs(k - 0.05) > 0.01
    e.request_value("pendulum.c_d", 0.02)  # another pendulum change keeps the tuning and its shown k
    e.tick(DT)
    assert e.scenario.pendulum.k == "resonant" and e.values["pendulum.k"] == pytest.approx(k, rel=1e-12)


def test_plane_pendulum_sliders_edit_one_bob_or_all():
    e = Engine(preset="Plane pendulums (three, in the spin plane)")
    ks = [p.k for p in e.scenario.plane_pendulums]
    e.request("bob", 1)
    e.tick(DT)
    e.request_value("pendulum.k", 0.9)
    e.tick(DT)
    assert e.error == "" and [p.k for p in e.scenario.plane_pendulums] == [ks[0], 0.9, ks[2]]
    assert e.values["pendulum.k"] == 0.9
    e.request("bob", 0)
    e.tick(DT)
    assert e.values["pendulum.k"] == ks[0]  # the sliders show the chosen bob
    e.request("bob", None)
    e.tick(DT)
    e.request_value("pendulum.k", 0.7)  # every bob, after the per-bob change: the latest move wins
    e.tick(DT)
    assert [p.k for p in e.scenario.plane_pendulums] == [0.7, 0.7, 0.7]
    with pytest.raises(physics.ScenarioError, match="names no bob"):
        controls.apply_changes(e.scenario, {"pendulum.k#7": 0.1})


def test_the_polhode_lies_on_the_drawn_inertia_ellipsoid():
    e = Engine(preset="Asymmetric body: intermediate-axis flip")
    e.request("polhode", True)
    fr = ticks(e, 600)  # 10 s: the flip carries omega across the ellipsoid
    p = fr.polhode
    axes = e.ellipsoid()  # the drawn semi-axes: sum((p / axes)^2) = 1 on its surface
    assert len(p) > 10
    np.testing.assert_allclose(np.sum((p / axes) ** 2, axis=1), 1.0, rtol=1e-12)
    assert np.ptp(p, axis=0).max() > axes.min()  # it travels across the ellipsoid
    e.request("polhode", False)
    assert ticks(e, 1).polhode is None


def test_overlays_and_badge_for_the_pendulum_systems():
    e = Engine(preset="Spherical pendulum damper, resonant")
    badge = e.badge(block=True)
    assert ": not here (" in badge and ("auto → full" in badge or "auto would run **full**" in badge)  # conditions
    e.request("overlay", "averaged")
    ticks(e, 2)
    assert e.wait_overlay() and e.error == ""
    t, theta, over, K, E = e.plot_data()
    assert np.all(np.isfinite(over)) and np.any(over != theta)
    # meridian pendulums: in-plane ones do not touch the nutation
    e = Engine(preset="Taylor's damper: three plane pendulums")
    e.request("overlay", "closed")
    ticks(e, 2)
    assert e.wait_overlay()  # linear theory's analysis runs off the loop thread too
    rate = physics.derived(e.scenario)["decay_rate_linear"]
    ot, oth = e.overlay
    assert rate > 0 and oth[-1] == pytest.approx(oth[0] * math.exp(-rate * ot[-1]), rel=1e-12)
    assert "plane pendulums have only the full model" in e.badge(block=True)


def _slow_preset() -> str:
    """Seed 004's Fig. 4 counterpart: its suggested warp is about 6000x, more than one frame can integrate."""
    return next(n for n in presets.preset_names() if "(|Gamma2| = 100" in n and "Fig. 4" in n)


STEP_COST_S = 1e-4  # fake wall seconds one integrator step costs: a machine too slow for the preset's warp
FRAME_OVERHEAD_S = 5e-4  # fake wall seconds a frame costs besides integrating


def _play_like_the_loop(e: Engine, frames: int, monkeypatch) -> list[float]:
    """Ticks with the wall time since the last one, as the session's loop does (a slow frame makes the next
    one integrate more: the spiral that stalled the tab), on a fake clock driven by counts: wall time is
    STEP_COST_S per integrator step taken plus FRAME_OVERHEAD_S per frame. Returns each frame's wall time."""
    state = {"steps": 0, "frames": 0}
    seen = {"run": e.run, "n": e.run.nsteps}

    def fake_clock() -> float:
        if e.run is not seen["run"]:
            seen["run"], seen["n"] = e.run, 0
        state["steps"] += e.run.nsteps - seen["n"]
        seen["n"] = e.run.nsteps
        return STEP_COST_S * state["steps"] + FRAME_OVERHEAD_S * state["frames"]

    monkeypatch.setattr(time, "perf_counter", fake_clock)
    walls = []
    last = fake_clock()
    for _ in range(frames):
        state["frames"] += 1
        now = fake_clock()
        e.tick(now - last)
        walls.append(fake_clock() - now)
        last = now
    return walls


def test_a_frame_integrates_within_its_budget_and_the_clock_slows_instead(monkeypatch):
    """Counts, not this machine's speed: with every step costing STEP_COST_S, an unbudgeted frame would
    integrate the whole warp's worth (hundreds of steps a frame, growing); the budget holds each frame near
    TICK_BUDGET_S and the simulated clock falls behind the warp instead."""
    from app.state import TICK_BUDGET_S

    e = Engine(preset=_slow_preset())
    assert e.warp > 1000
    _play_like_the_loop(e, 5, monkeypatch)  # the probe after the start, and the rate measured
    t0, steps0 = e.run.t, e.run.nsteps
    walls = _play_like_the_loop(e, 30, monkeypatch)
    steps_per_frame = (e.run.nsteps - steps0) / 30
    assert steps_per_frame * STEP_COST_S < 2 * TICK_BUDGET_S, steps_per_frame
    assert max(walls) < 4 * TICK_BUDGET_S, max(walls)
    wall = sum(walls) + 0.0
    assert 0 < (e.run.t - t0) < 0.8 * wall * e.warp  # the simulated clock fell behind the warp instead
    assert e.achieved_warp < 0.8 * e.warp and e.run.status == "running"


def test_the_first_frame_after_a_change_never_falls_below_real_time():
    e = Engine()
    ticks(e, 3)
    e.request("warp", 100.0)
    t0 = e.run.t
    e.tick(DT)  # a probe: far less than 100 x DT, but at least DT
    assert DT * (1 - 1e-12) <= e.run.t - t0 < 100 * DT


def test_the_badge_is_worked_out_in_the_background():
    e = Engine(preset="Taylor's damper: three plane pendulums")
    first = e.badge()
    assert "working out" in first  # returned at once, not after the 0.2-0.4 s analysis
    deadline = time.perf_counter() + 60
    while "working out" in e.badge() and time.perf_counter() < deadline:
        time.sleep(0.02)
    assert e.badge() == e.badge(block=True) and "auto" in e.badge().split(" · ")[0]
