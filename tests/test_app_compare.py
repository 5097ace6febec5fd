"""Compare mode, headless (app/engine/compare.py): a second run with one difference on the engine's clock. Both runs
reach the same t each tick; an edit reaches both with each run's |K| kept and the difference kept; one run
braking or faulting leaves the other going; bad differences are refused with a message naming them."""

from __future__ import annotations

import numpy as np
import pytest

from app.engine import compare, controls
from app.engine.engine import Engine
from app.state import FRAME_HZ

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")
DT = 1.0 / FRAME_HZ
K_REL = 1e-9  # relative: an edit carries the inertial angular momentum (physics.carry_state)


def ticks(engine: Engine, n: int) -> None:
    for _ in range(n):
        engine.tick(DT)


def on(engine: Engine, spec) -> compare.Comparison:
    engine.request("compare", spec)
    engine.tick(DT)
    assert engine.error == ""
    assert isinstance(engine.compare, compare.Comparison)
    return engine.compare


def K(run) -> float:
    return float(run.last.K[0])


def test_both_runs_advance_to_the_same_t_each_tick():
    e = Engine()
    ticks(e, 5)
    c = on(e, ("mass.m", 0.0))
    assert e.run.t == c.run.t  # turned on, both start again from t = 0 together
    times = []
    for _ in range(20):
        e.tick(DT)
        assert c.run.t == e.run.t
        times.append(e.run.t)
    assert times[-1] > times[0] > 0  # they moved
    e.request("step")
    e.tick(DT)
    assert c.run.t == e.run.t  # a single step advances both too


def test_an_edit_reaches_both_runs_keeping_each_K_and_the_difference():
    e = Engine()
    c = on(e, ("mass.chi", 1.0))
    ticks(e, 10)
    K1, K2 = K(e.run), K(c.run)
    e.request_value("mass.m", 0.3)
    e.tick(DT)
    assert e.error == ""
    assert e.scenario.mass.m == pytest.approx(0.3) and c.scenario.mass.m == pytest.approx(0.3)
    assert e.scenario.mass.chi == pytest.approx(5.0) and c.scenario.mass.chi == pytest.approx(1.0)  # kept
    assert abs(K(e.run) / K1 - 1) < K_REL
    assert abs(K(c.run) / K2 - 1) < K_REL
    assert c.run.t == e.run.t


def test_with_and_without_the_mass_an_edit_keeps_both_K():
    e = Engine()
    c = on(e, ("mass.m", 0.0))
    ticks(e, 5)
    assert c.scenario.mass is None and e.scenario.mass is not None  # m = 0 removes the mass (physics)
    K1, K2 = K(e.run), K(c.run)
    e.request_value("body.C", 1.5)
    e.tick(DT)
    assert e.scenario.body.C == pytest.approx(1.5) and c.scenario.body.C == pytest.approx(1.5)
    assert c.scenario.mass is None  # the difference is kept
    assert abs(K(e.run) / K1 - 1) < K_REL and abs(K(c.run) / K2 - 1) < K_REL
    labels = compare.readout_md(e)
    assert "m = 0.2 kg" in labels and "m = 0 kg" in labels


@pytest.mark.parametrize("spec", [("mass.m", 0.0), ("fidelity", "averaged"), ("mass.chi", 1.0), ("body.C", 1.6)])
def test_compared_runs_start_from_the_same_K_and_theta(spec):
    """Issue 24: with and without the mass |K| started at 3.58 against 3.0, full against averaged at 3.37
    against 3.0 (the mass's start adds to K): the runs compared one difference and another, unasked. Both now
    start from the first run's K (size and direction) and attitude, so the same theta(0)."""
    e = Engine()
    c = on(e, spec)
    first, second = e.plot_all.values()[0], c.plot_all.values()[0]  # (t, theta, |K|, E) at the start
    assert first[0] == second[0] == 0.0
    assert second[2] == pytest.approx(first[2], rel=K_REL) and second[1] == pytest.approx(first[1], abs=1e-9)
    ticks(e, 3)
    assert c.run.t == e.run.t > 0  # and they go on together


def test_a_difference_in_the_start_itself_starts_the_second_run_there():
    e = Engine()
    c = on(e, (next(p.key for p in controls.PARAMS if p.restarts and "theta" in p.key), 0.3))
    assert c.plot_all.values()[0, 1] < e.plot_all.values()[0, 1] - 0.2  # asked for: another theta(0)


def test_a_fidelity_difference_runs_the_other_model():
    e = Engine()
    c = on(e, ("fidelity", "averaged"))
    ticks(e, 5)
    assert e.run.fidelity == "full" and c.run.fidelity == "averaged"
    assert c.run.t == e.run.t
    assert "run 2: fidelity averaged" in compare.readout_md(e)


def test_when_one_run_brakes_to_rest_the_other_goes_on():
    e = Engine()
    e.request_value("control.b", 0.02)
    e.tick(DT)
    c = on(e, ("control.b", 0.0))
    t_start = c.run.t
    e._advance(300.0)  # the braking time is |K| / b, about 180 s: the first run stops on the way
    assert e.run.ended and e.run.status == "braked"
    assert not c.run.ended and c.run.t == pytest.approx(t_start + 300.0)
    t1 = e.run.t
    e._advance(5.0)
    assert e.run.t == t1 and c.run.t == pytest.approx(t_start + 305.0)
    md = compare.readout_md(e)
    assert "status = braked" in md.splitlines()[1] and "status" not in md.splitlines()[2]


def test_when_the_second_run_faults_the_first_goes_on(monkeypatch):
    e = Engine()
    c = on(e, ("mass.m", 0.0))

    def broken(*_a, **_k):
        raise FloatingPointError("overflow in the second run")

    monkeypatch.setattr(c.run, "advance", broken)
    t0 = e.run.t
    ticks(e, 3)
    assert c.run.status == "fault" and "overflow" in c.run.message
    assert e.run.t > t0 and e.run.status == "running"
    assert "status = fault" in compare.readout_md(e).splitlines()[2]


def test_turning_compare_off_returns_to_one_run():
    e = Engine()
    on(e, ("mass.m", 0.0))
    e.request("compare", "off")
    t0 = e.run.t
    e.tick(DT)
    assert e.compare is None and compare.readout_md(e) == ""
    assert e.run.t > t0  # the first run went on, not restarted


@pytest.mark.parametrize(("spec", "words"), [
    (("nope.x", 1.0), "'nope.x' is not a slider's parameter"),
    (("fidelity", "exact"), "fidelity 'exact' is not one of"),
    (("mass.m", float("nan")), "m = nan is not a finite number"),
    ("mass", "is not a difference"),
])
def test_a_bad_difference_is_refused_naming_it(spec, words):
    e = Engine()
    e.request("compare", spec)
    e.tick(DT)
    assert words in e.error and e.compare is None


def test_a_parameter_the_scene_lacks_is_refused_and_a_new_scene_turns_compare_off():
    e = Engine(preset="Spherical pendulum damper, resonant")
    e.request("compare", ("mass.chi", 1.0))
    e.tick(DT)
    assert "mass.chi" in e.error and "spherical_pendulum" in e.error and e.compare is None
    e = Engine()
    on(e, ("mass.chi", 1.0))
    e.request("preset", "Spherical pendulum damper, resonant")
    e.tick(DT)
    note = compare.readout_md(e)  # said under the readouts
    assert e.compare is None and note.startswith("compare mode off:") and "mass.chi" in note


def test_the_second_frame_is_drawable():
    e = Engine()
    on(e, ("mass.rho", 1.0))
    ticks(e, 3)
    fr = compare.frame_of(e)
    for v in (fr.body_wxyz, fr.K_vec, fr.omega_vec, fr.axis_vec, fr.part("mass").centre):
        assert np.all(np.isfinite(v))
    np.testing.assert_allclose(fr.K_vec / np.linalg.norm(fr.K_vec), [0, 0, 1], atol=1e-9)  # its K up too
    assert controls.values_of(e.compare.scenario)["mass.rho"] == 1.0 and e.scenario.mass.rho == 1.5


def test_undo_takes_both_runs_back_to_one_t():
    e = Engine()
    c = on(e, ("mass.chi", 1.0))
    ticks(e, 5)
    t_edit, K2 = c.run.t, K(c.run)
    e.request_value("mass.m", 0.3)
    ticks(e, 5)
    assert c.scenario.mass.m == pytest.approx(0.3)
    e.request("undo")
    e.tick(DT)
    assert e.compare is c and e.scenario.mass.m == pytest.approx(0.2) and c.scenario.mass.m == pytest.approx(0.2)
    assert c.scenario.mass.chi == pytest.approx(1.0)
    assert c.run.t == e.run.t and t_edit < e.run.t < t_edit + 2 * DT  # back to the change, then one tick on
    assert abs(K(c.run) / K2 - 1) < K_REL


def test_undo_to_before_compare_mode_turns_it_off():
    e = Engine()
    e.request_value("mass.m", 0.3)
    e.tick(DT)
    on(e, ("mass.chi", 1.0))
    e.request("undo")
    e.tick(DT)
    assert e.compare is None and "before it was turned on" in compare.readout_md(e)


def test_the_panel_overlays_both_runs_and_turning_off_restores_one():
    """Headless panel (tests/test_app_words.py's recording GUI): the overlaid charts' legends name both runs,
    the single run's charts hide and come back."""
    from types import SimpleNamespace

    from test_app_words import _RecordingGui

    from app.panel.panel import Panel

    e = Engine()
    panel = Panel(SimpleNamespace(gui=_RecordingGui(), scene=None, client_id=0), e)
    e.request("compare", ("mass.m", 0.0))
    for _ in range(3):
        panel.update(e.tick(DT), plots_now=True)
    labels = [s["label"] for h in panel.compare_plots.handles.values() for s in h.series[1:]]
    assert sum(lab.startswith("m = 0.2 kg: ") for lab in labels) == 3
    assert sum(lab.startswith("m = 0 kg: ") for lab in labels) == 3
    assert all(h.visible for h in panel.compare_plots.handles.values())
    assert not any(h.visible for h in panel.plots.handles.values())
    assert "run 2: theta = " in panel.compare_md.content
    e.request("compare", None)
    for _ in range(2):
        panel.update(e.tick(DT), plots_now=True)
    assert panel.compare_md.content == "" and not any(h.visible for h in panel.compare_plots.handles.values())
    assert panel.plots.handles["theta"].visible and panel.plots.handles["E"].visible


def test_a_compare_parameter_not_offered_is_refused_in_words_not_raised():
    """A client's "parameter" value that is not one of the dropdown's (issue 24: StopIteration in the panel's
    callback) is refused with a note naming it and what is offered; nothing is requested of the engine."""

    from test_app_words import _RecordingGui

    from app.panel.compare_panel import PARAMETER, ComparePanel

    e = Engine()
    panel = ComparePanel(_RecordingGui(), e)
    panel.mode.value = PARAMETER
    panel.value.value = 0.5
    for handle in (panel.param, panel.value):
        panel.param.value = "not a parameter"
        before = panel._seq
        handle.fire()
        assert panel._seq == before
        assert e.error.startswith("parameter: 'not a parameter' refused; expected one of ")
        assert panel._labels()[0] in e.error


def test_several_sliders_at_once_are_one_difference():
    """A design's optimum sets two or three sliders: the second run takes them all, its labels name them all, and a
    bad pair is refused naming it."""
    e = Engine()
    c = on(e, (compare.SLIDERS, (("mass.chi", 2.5), ("mass.m", 0.05))))
    assert c.scenario.mass.chi == 2.5 and c.scenario.mass.m == 0.05
    assert e.scenario.mass.chi != 2.5 and e.scenario.mass.m != 0.05
    assert "chi = 2.5" in c.diff.label() and "m = 0.05" in c.diff.label()
    assert "chi = " in c.diff.own_label(e.scenario) and "m = " in c.diff.own_label(e.scenario)
    ticks(e, 5)
    assert c.run.t == e.run.t > 0
    for bad, words in ((("mass.chi", 1.0), ("mass.chi", 2.0)), "different sliders"), \
                      ((("mass.nope", 1.0),), "is not a slider's parameter"), \
                      ((("mass.m", float("nan")),), "is not a finite number"), \
                      ("chi", "not a list of"):
        with pytest.raises(ValueError, match=words):
            compare.parse((compare.SLIDERS, bad))
