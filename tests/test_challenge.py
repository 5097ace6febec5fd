"""The braking challenge, headless (issue 25, point 2), through a tab's engine: the levels' optimal braking time
T against seed 004's closed form written out here and against the full model's own run of the optimal law; a
scripted player that fires the thruster most nearly opposite J w finishes within sqrt(3) T (the best body axis
is at most arccos(1/sqrt 3) from -K, so |K| falls at least at b/sqrt 3); a player that does nothing never
finishes; the score's arithmetic; bad input."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import physics
from app.engine import challenge
from app.engine.buffers import PENDING_EACH
from app.engine.engine import Engine

DT = 0.05  # the players' reaction time (s): one decision per step


def started(level: str, seed: int = 0) -> Engine:
    eng = Engine()
    eng.request("challenge", (level, seed))
    eng._apply_pending()
    assert eng.error == "" and eng.challenge is not None
    return eng


def play(eng: Engine, player) -> challenge.Challenge:
    ch = challenge.play(eng, player, DT)
    assert ch.over
    return ch


scripted = challenge.scripted


def closed_form_T(sc: physics.Scenario, K0: float) -> float:
    """Seed 004 eq. (11): |K|' = -b - lambda |K| reaches 0 at ln(1 + lambda K0 / b) / lambda (K0 / b without a
    medium)."""
    b = sc.control.b
    lam = sc.medium.lambda_ if sc.medium is not None else 0.0
    return K0 / b if lam == 0 else math.log1p(lam * K0 / b) / lam


@pytest.mark.parametrize("level", challenge.LEVELS)
def test_the_optimal_law_s_body_stops_at_the_closed_form_t(level):
    eng = started(level)
    ch = eng.challenge
    assert ch.T == pytest.approx(closed_form_T(ch.optimal, ch.K0), rel=1e-12)
    assert 10 < ch.T < 30  # a person's race
    while eng.compare.run.status == "running" and eng.run.t < 2 * ch.T:
        eng._advance(1.0)
    assert eng.compare.run.status == "braked"
    assert eng.compare.run.t == pytest.approx(ch.T, rel=1e-6)  # the full model's own stop


@pytest.mark.parametrize("level", challenge.LEVELS)
@pytest.mark.parametrize("seed", [0, 7])
def test_a_scripted_player_stops_the_body_within_sqrt3_t(level, seed):
    eng = started(level, seed)
    ch = play(eng, scripted)
    assert ch.finished_at is not None and not ch.out_of_time
    assert ch.T < ch.finished_at <= math.sqrt(3) * ch.T, (ch.finished_at, ch.T)
    assert ch.score == pytest.approx(ch.T / ch.finished_at, rel=1e-15)
    assert not eng.playing and ch.thruster is None  # the attempt ended: paused, thruster off
    rows = eng.plot_all.values()
    before, after = rows[rows[:, 0] <= ch.finished_at], rows[rows[:, 0] > ch.finished_at]
    assert before[-1, 2] >= challenge.FINISH * ch.K0 > after[0, 2]  # |K| crosses 1 % of its start there
    assert "score T / T_you" in challenge.readout_md(eng)


def test_the_race_s_words_give_k_in_the_body_s_axes():
    """K's body components, against the full model's own body-frame momentum: J w for a rigid body."""
    eng = started("rigid", 3)
    eng._advance(2.0)
    body = eng.scenario.body
    G = np.array([body.A, body.B, body.C]) * eng.run.last.omega[0]
    np.testing.assert_allclose(challenge.K_in_body(eng), G / np.linalg.norm(G), atol=1e-12)
    words = challenge.readout_md(eng)
    shown = [float(x) for x in re.findall(r"e\d ([+-]\d\.\d\d)", words)]
    np.testing.assert_allclose(shown, G / np.linalg.norm(G), atol=0.006)


@pytest.mark.parametrize("level", challenge.LEVELS)
def test_a_player_who_does_nothing_never_finishes(level):
    eng = started(level)
    ch = play(eng, lambda eng: None)
    assert ch.out_of_time and ch.finished_at is None and ch.score is None
    assert eng.run.last.K[0] > challenge.FINISH * ch.K0
    assert eng.run.t >= challenge.LIMIT * ch.T
    assert "out of time" in challenge.readout_md(eng)


def test_the_finish_is_interpolated_between_samples_and_scored_t_over_it():
    ch = challenge.Challenge.new("rigid", 0)
    ch.K0, ch.T = 1.0, 1.5
    ch.check(np.array([[0.0, 0, 1.0, 0], [1.0, 0, 0.5, 0]]))
    assert ch.finished_at is None
    ch.check(np.array([[2.0, 0, 0.005, 0]]))  # a row alone crossing: its own t
    assert ch.finished_at == 2.0
    ch = challenge.Challenge.new("rigid", 0)
    ch.K0, ch.T = 1.0, 1.5
    ch.check(np.array([[1.0, 0, 0.5, 0], [2.0, 0, 0.005, 0]]))
    assert ch.finished_at == pytest.approx(1.0 + (0.5 - 0.01) / (0.5 - 0.005), rel=1e-15)
    assert ch.score == pytest.approx(1.5 / ch.finished_at, rel=1e-15)


def test_one_seed_gives_every_tab_the_same_start_and_seeds_differ():
    a, b, c = started("with_mass", 42), started("with_mass", 42), started("with_mass", 43)
    np.testing.assert_array_equal(a.run.last.omega, b.run.last.omega)
    assert not np.allclose(a.run.last.omega, c.run.last.omega)
    lo, hi = challenge.THETA0
    assert all(lo <= challenge.start_angle(s) <= hi for s in range(200))


def test_a_thruster_stops_when_not_pressed_again_and_the_attempt_resets_and_ends():
    eng = started("rigid")
    eng.request("thrust", "-e3")
    eng._apply_pending()
    assert eng.challenge.thruster == "-e3" and eng.scenario.control.law == "-e3"
    challenge.before_advance(eng, now=eng.challenge.until + 1e-3)
    assert eng.challenge.thruster is None and eng.scenario.control.b == 0.0
    eng._advance(2.0)
    eng.request("reset")
    eng._apply_pending()
    assert eng.run.t == 0.0 and eng.challenge is not None and eng.compare is not None
    eng.request_value("body.A", 1.2)  # a parameter changed: no longer the level's race
    eng._apply_pending()
    assert eng.challenge is None and eng.compare is None and eng.error == ""


def test_let_go_stops_the_thruster_at_once_and_a_repeat_sent_before_it_is_dropped():
    eng = started("rigid")
    eng.request("thrust", "+e2")
    eng._apply_pending()
    assert eng.challenge.thruster == "+e2"
    eng._advance(0.05)  # held for a tick
    eng.request("thrust", "off")  # the page's Thrusters off, clicked as the key is let go
    eng.request("thrust", "+e2")  # a hold message the thread pool handled after it
    eng._apply_pending()
    assert eng.challenge.thruster is None and eng.scenario.control.b == 0.0
    eng.challenge.released = ("+e2", eng.challenge.released[1] - challenge.RELEASE_GRACE_S)
    eng.request("thrust", "+e2")  # pressed again later: fires
    eng._apply_pending()
    assert eng.challenge.thruster == "+e2"


def test_a_tap_between_two_ticks_fires_for_the_next_tick_and_then_stops():
    """Pressed and let go before the loop advances (a busy server's tick is longer than a quick tap): the thruster
    fires for the tick that follows and is off after it, so a tap is never lost."""
    eng = started("rigid")
    K0 = float(eng.run.last.K[0])
    eng.request("thrust", "-e3")
    eng.request("thrust", "off")
    eng._apply_pending()
    assert eng.challenge.thruster == "-e3" and eng.challenge.release_due
    eng._advance(0.1)
    ch = eng.challenge
    assert ch.thruster is None and eng.scenario.control.b == 0.0 and not ch.release_due
    assert ch.fired == pytest.approx(0.1, rel=1e-12)
    K1 = float(eng.run.last.K[0])
    assert K1 < K0  # the tap braked: |K| falls at most b per second, and by at least a part of it
    assert K0 - K1 <= ch.b * 0.1 * (1 + 1e-9)
    eng._advance(0.1)  # and no more after it
    assert ch.fired == pytest.approx(0.1, rel=1e-12)
    eng.request("thrust", "+e1")
    eng.request("thrust", "off")
    eng._apply_pending()
    eng.challenge.released = ("+e1", eng.challenge.released[1] - challenge.RELEASE_GRACE_S)
    eng.request("thrust", "+e1")  # pressed again before the tick: held, not tapped
    eng._apply_pending()
    eng._advance(0.1)
    assert ch.thruster == "+e1"


def test_a_tap_fires_for_as_long_as_it_was_held_and_the_tick_goes_on_without_it():
    """A tick longer than the tap: the thruster fires for the tap's held seconds (at least TAP_MIN_S), then the
    same tick goes on with it off, so a student's quick taps brake by little, as on a quiet server."""
    eng = started("rigid")
    eng.request("thrust", "+e1")
    eng.request("thrust", "off")
    eng._apply_pending()
    ch = eng.challenge
    assert ch.tap_s == pytest.approx(challenge.TAP_MIN_S)  # let go at once: a frame's worth
    ch.tap_s = 0.06  # as held by a hand
    t0 = eng.run.t
    eng.tick(0.25)
    assert ch.thruster is None and not ch.release_due
    assert ch.fired == pytest.approx(0.06, rel=1e-12)
    assert eng.run.t - t0 > 0.06  # the tick went on past the tap


def test_a_flood_of_thrusts_queues_a_bounded_few_and_the_latest_counts():
    """A raw client's hold messages at any rate, alternating thrusters (each switch a retune): at most
    PENDING_EACH wait for the next tick, the latest kept."""
    eng = started("rigid")
    for i in range(10_000):
        eng.request("thrust", "+e1" if i % 2 else "-e1")
    assert sum(a == "thrust" for a, _ in eng._actions) == PENDING_EACH
    eng._apply_pending()
    assert eng.challenge.thruster == "+e1" and eng.error == ""


@pytest.mark.parametrize("action, value, words", [
    ("challenge", ("rigid", -1), "challenge start number -1 is not a whole number from 0 to 9999"),
    ("challenge", ("rigid", 1e308), "challenge start number 1e+308"),
    ("challenge", ("rigid", "nan"), "challenge start number 'nan'"),
    ("challenge", ("spinning top", 0),
     "challenge level 'spinning top' is not one of rigid, in_medium, with_mass, prolate"),
    ("challenge", "rigid", "challenge: 'rigid' is not (level, seed)"),
    ("thrust", "+e4", "thrust '+e4': expected one of +e1, -e1, +e2, -e2, +e3, -e3 or off"),
    ("thrust", "+e1", "thrust: no braking challenge is running"),
])
def test_bad_input_is_refused_in_words_and_the_scene_stays(action, value, words):
    eng = Engine()
    before = eng.scenario
    eng.request(action, value)
    eng._apply_pending()
    assert words in eng.error
    assert eng.scenario is before and eng.challenge is None
