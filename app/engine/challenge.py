"""The braking challenge (issue 25, point 2): a student stops a spinning body by hand, with thrusters of torque b
along its axes (physics: ``control.law`` "+e1" ... "-e3"), and races the time-optimal law -b K/|K| of seed 004,
whose body runs beside as compare mode's second run, on the same clock. No viser here.

A level is a scenario in assets/challenge whose first line is ``# challenge: TITLE``; a seed picks the start's
nutation angle, so every tab given the same level and seed races from the same start. The attempt ends when the
student's |K| falls below FINISH of its start (the score is T / T_student, T the optimal law's closed-form braking
time, seed 004 eq. (11), the medium included) or, out of time, at LIMIT T. A thruster fires from a press (a button
or its key) until it is let go (the page then clicks Thrusters off), or HOLD_S after the last press if that word
is lost: viser's buttons repeat while held (10 times a second), the page's key script likewise. A tap (pressed and let
go between two ticks: a busy loop ticks slower than a quick tap) fires for as long as it was held, at least
TAP_MIN_S, at the start of the next tick, which goes on with the thruster off.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import physics

from .compare import CHALLENGE, Comparison, Difference

LEVELS_DIR = Path(__file__).resolve().parents[2] / "assets" / "challenge"
LEVELS = ("rigid", "in_medium", "with_mass", "prolate")  # in the order a class climbs them
TITLE_LINE = "# challenge: "
THRUSTERS = physics.THRUSTERS  # one button each
KEYS = dict(zip(THRUSTERS, ("D", "A", "W", "S", "E", "Q"), strict=True))  # the page's keys (app.panel.challenge)
FINISH = 0.01  # stopped: |K| below 1 % of its start
LIMIT = 3.0  # out of time at 3 T: doing nothing in the medium takes ln(100) / lambda = 230 s, 14 T
# a thruster fires until this long after its last press: held buttons repeat every 0.1 s, but a page busy drawing
# (software WebGL) sends them up to 0.3 s apart, which at 0.25 s switched a held thruster off and on
HOLD_S = 0.5
# the page says "off" when a key or button is let go (the Thrusters off button, clicked by its script): a repeat of
# the same thruster handled within this after it was sent before it, and is dropped
RELEASE_GRACE_S = 0.2
TAP_MIN_S = 1 / 30  # a tap fires at least a frame's worth, however short the page made it
SEEDS = 10_000  # a seed is a whole number in [0, SEEDS)
THETA0 = (0.35, 1.1)  # the start's nutation angle (rad), drawn from the seed


def level_title(level: str) -> str:
    """A level's title: its file's first line ``# challenge: TITLE``."""
    first = (LEVELS_DIR / f"{_level(level)}.toml").read_text().splitlines()[0]
    return first[len(TITLE_LINE):].strip() if first.startswith(TITLE_LINE) else level


def _level(level) -> str:
    if level not in LEVELS:
        raise ValueError(f"challenge level {level!r} is not one of {', '.join(LEVELS)}")
    return level


def _seed(seed) -> int:
    try:
        s = float(seed)
    except (TypeError, ValueError):
        s = math.nan
    if not (math.isfinite(s) and s == int(s) and 0 <= s < SEEDS):
        raise ValueError(f"challenge start number {seed!r} is not a whole number from 0 to {SEEDS - 1}")
    return int(s)


def start_angle(seed: int) -> float:
    """The nutation angle theta0 (rad) a seed starts from: the same on every machine (numpy's PCG64)."""
    return float(np.random.default_rng(_seed(seed)).uniform(*THETA0))


def best_thruster(G_body: np.ndarray) -> str:
    """The thruster most nearly opposite ``G_body`` (body axes): along the axis of G's largest component, against
    it. What the scripted player fires, and what a student would if they read the body's axes perfectly."""
    i = int(np.argmax(np.abs(G_body)))
    return ("-" if G_body[i] > 0 else "+") + f"e{i + 1}"


def scripted(eng) -> str:
    """The scripted player's pick: the thruster most nearly opposite the student's J w (body axes)."""
    body = eng.scenario.body
    return best_thruster(np.array([body.A, body.B, body.C]) * eng.run.last.omega[0])


def play(eng, player, reaction_s: float) -> Challenge:
    """Race the attempt ``eng`` runs to its end without a page: every ``reaction_s`` simulated seconds the
    ``player(eng)`` names a thruster to hold (or None), as the loop would apply it. The benchmark's and the
    tests' player (bench/challenge.py, tests/test_challenge.py)."""
    ch = eng.challenge
    if ch is None:
        raise ValueError("play: no braking challenge is running")
    for _ in range(int(LIMIT * ch.T / reaction_s) + 10):
        if ch.over:
            break
        fire = player(eng)
        if fire is not None:
            eng.request("thrust", fire)
        eng._apply_pending()
        before_advance(eng, now=-math.inf if fire is not None else math.inf)  # held while named, else let go
        eng._advance(reaction_s)
    return ch


@dataclass
class Challenge:
    """One attempt: the level, the seed, the optimal law's scenario and braking time, and the race's state."""

    level: str
    seed: int
    optimal: physics.Scenario  # the level's scene under the optimal law -b K/|K|
    T: float  # the optimal law's braking time (s), seed 004 eq. (11)
    b: float  # the thrusters' torque (N m), the optimal law's bound
    K0: float = math.nan  # |K| at the start (set when the run starts)
    thruster: str | None = None  # firing now
    until: float = 0.0  # time.monotonic() at which the thruster stops unless pressed again
    finished_at: float | None = None  # the simulated t at which |K| fell below FINISH K0
    out_of_time: bool = False
    fired: float = 0.0  # simulated seconds with a thruster on
    released: tuple = (None, -math.inf)  # (thruster, time.monotonic()) of the last "off"
    # the thruster firing has not been through an advance yet: a let-go now waits for one (a tap, pressed and let
    # go between two ticks of a busy loop, would otherwise fire for no time at all)
    unfired: bool = False
    release_due: bool = False  # let go before its first advance: off after the next
    pressed_at: float = 0.0  # time.monotonic() at which the thruster firing now went on
    tap_s: float = 0.0  # a tap's held wall seconds (let go before its first advance)

    @classmethod
    def new(cls, level: str, seed) -> Challenge:
        base = physics.Scenario.load(LEVELS_DIR / f"{_level(level)}.toml")
        sc = base.with_values(**{"initial.theta0": start_angle(seed)})
        T = float(physics.derived(sc)["T"])
        return cls(level=level, seed=_seed(seed), optimal=sc, T=T, b=float(physics.brake_and_medium(sc)[0]))

    @property
    def title(self) -> str:
        return f"{level_title(self.level)} · start {self.seed}"

    def student(self, thruster: str | None) -> physics.Scenario:
        """The student's scene: the level's with ``thruster`` firing (torque b along it), or none: b = 0 under the
        level's own law, so that the b slider, after the attempt, brakes as it does in any scene."""
        return physics.with_thruster(self.optimal, thruster, self.b)

    @property
    def over(self) -> bool:
        return self.finished_at is not None or self.out_of_time

    @property
    def score(self) -> float | None:
        """T / T_student once stopped (1 is the optimal law's time; a hand that loses more time scores less)."""
        return None if self.finished_at is None else self.T / self.finished_at

    def check(self, rows: np.ndarray) -> None:
        """The plot rows (t, theta, |K|, E) of the last advance: stopped at the first t where |K| < FINISH K0
        (linear between samples), else out of time past LIMIT T."""
        if self.over or not len(rows):
            return
        target = FINISH * self.K0
        below = np.nonzero(rows[:, 2] < target)[0]
        if len(below):
            i = int(below[0])
            if i == 0:
                self.finished_at = float(rows[0, 0])
            else:
                (t0, K0), (t1, K1) = rows[i - 1, [0, 2]], rows[i, [0, 2]]
                self.finished_at = float(t0 + (t1 - t0) * (K0 - target) / (K0 - K1))
        elif rows[-1, 0] >= LIMIT * self.T:
            self.out_of_time = True


# ---- the engine's side: actions and what the loop does (app.engine.engine) -------------------------------
def start(eng, spec) -> None:
    """The "challenge" action: ``(level, seed)`` starts an attempt (the scene loaded from t = 0, the optimal law
    beside, real time); None or "off" ends it and leaves the scene as it is."""
    if spec is None or spec == "off":
        stop(eng)
        return
    try:
        level, seed = spec
    except (TypeError, ValueError):
        raise ValueError(f"challenge: {spec!r} is not (level, seed); levels: {', '.join(LEVELS)}") from None
    ch = Challenge.new(level, seed)
    stop(eng)  # an attempt running ends; this one starts after the load
    eng.compare = None
    eng._load(ch.student(None), f"challenge: {ch.title}")
    eng.challenge = ch
    eng.compare = Comparison(eng, Difference(CHALLENGE, "optimal"))
    eng._restarted()  # both runs from t = 0, one clock
    ch.K0 = float(eng.run.last.K[0])
    # T from the |K| the race starts with (a moving mass's quasistatic start carries a little more than G0), so that
    # the optimal law's own run stops at T: d|K|/dt = -b - lambda |K| whatever moves inside
    b, lam = physics.brake_and_medium(ch.optimal)
    ch.T = float(physics.get_system(ch.optimal.system).braking_time(ch.K0, b, lam))
    eng.clock.warp = 1.0  # a person's hands: real time
    eng.playing = True
    eng.scene_changed = eng.plots_changed = True


def stop(eng) -> None:
    """No attempt any more: the thruster off, compare mode off; the scene stays as it is."""
    ch = getattr(eng, "challenge", None)
    if ch is None:
        return
    eng.challenge = None
    if ch.thruster is not None:
        eng.run.retune(ch.student(None), keep_state=True)
    if eng.compare is not None and eng.compare.diff.key == CHALLENGE:
        eng.compare = None
    eng.scene_changed = eng.plots_changed = True


def thrust(eng, value) -> None:
    """The "thrust" action: fire ``value`` (one of THRUSTERS) until HOLD_S from now, or stop it (None or "off").
    Ignored once the attempt is over; refused without one."""
    ch = getattr(eng, "challenge", None)
    if value is not None and value != "off" and value not in THRUSTERS:
        raise ValueError(f"thrust {value!r}: expected one of {', '.join(THRUSTERS)} or off")
    if ch is None:
        raise ValueError("thrust: no braking challenge is running (start one in the Braking challenge folder)")
    if ch.over:
        return
    fire = None if value == "off" else value
    now = time.monotonic()
    if fire is None:
        ch.released = (ch.thruster, now)
        if ch.thruster is not None and ch.unfired:
            ch.release_due = True  # a tap: it fires as long as it was held, in the next tick, then stops
            ch.tap_s = max(now - ch.pressed_at, TAP_MIN_S)
            return
    elif ch.released[0] == fire and now - ch.released[1] < RELEASE_GRACE_S:
        return  # a repeat sent before the release, handled after it (viser runs callbacks in a thread pool)
    else:
        ch.until = now + HOLD_S
        ch.release_due = False  # pressed again: held, not tapped
    if fire != ch.thruster:
        _switch(eng, ch, fire)


def _switch(eng, ch: Challenge, fire: str | None) -> None:
    """The student's run goes on from its state with ``fire`` on (not an edit: nothing to undo, nothing logged)."""
    eng.run.retune(ch.student(fire), keep_state=True)
    ch.thruster = fire
    ch.unfired, ch.release_due = fire is not None, False
    ch.pressed_at = time.monotonic()


def tap_seconds(eng) -> float | None:
    """Simulated seconds the next advance fires a tap for before it stops (None: no tap waiting)."""
    ch = eng.challenge
    if ch is None or ch.thruster is None or not ch.release_due:
        return None
    return ch.tap_s * eng.warp


def before_advance(eng, now: float | None = None) -> None:
    """A thruster not pressed again within HOLD_S stops."""
    ch = eng.challenge
    if ch is not None and ch.thruster is not None and (now if now is not None else time.monotonic()) > ch.until:
        _switch(eng, ch, None)


def after_advance(eng, rows: np.ndarray, dt: float) -> None:
    """The rows this tick recorded: stopped or out of time ends the attempt (paused, thruster off)."""
    ch = eng.challenge
    if ch is None or ch.over:
        return
    if ch.thruster is not None and dt > 0:
        ch.fired += dt
        ch.unfired = False
        if ch.release_due:
            _switch(eng, ch, None)
    ch.check(rows)
    if ch.over:
        if ch.thruster is not None:
            _switch(eng, ch, None)
        eng.playing = False


def K_in_body(eng) -> np.ndarray:
    """The student's K in their body's axes, as a fraction of |K| (what the momentum sphere draws)."""
    K = eng.run.momentum()
    n = float(np.linalg.norm(K))
    q = eng.run.last.quat[0]
    return physics.rotate(physics.qconj(q), K) / n if n > 0 else np.zeros(3)


def aim_words(eng) -> str:
    """K's body components in words ("e1 +0.31 · e2 -0.12 · e3 +0.94"): a thruster against the largest brakes
    best, and nutation turns them while the student aims."""
    return " · ".join(f"e{i + 1} {x:+.2f}" for i, x in enumerate(K_in_body(eng)))


def readout_md(eng) -> str:
    """The race in words: the level, the clock, both |K|, the optimal T, and the score once stopped."""
    ch = eng.challenge
    if ch is None:
        return ""
    t = float(eng.run.t)
    K = float(eng.run.last.K[0])
    K_opt = float(eng.compare.run.last.K[0]) if eng.compare is not None else math.nan
    lines = [f"**Braking challenge** · {ch.title}",
             f"elapsed {t:.1f} s · optimal T = {ch.T:.1f} s · time limit {LIMIT * ch.T:.0f} s",
             f"your |K| = {K:.3g} ({100 * K / ch.K0:.0f} % of its start) · the optimal law's |K| = {K_opt:.3g}"
             " kg m^2/s",
             "K along your body's axes: " + aim_words(eng),
             "thruster: " + (f"{ch.thruster} (torque {ch.b:g} N m)" if ch.thruster else "off")]
    if ch.score is not None:
        lines.append(f"**stopped in {ch.finished_at:.2f} s · score T / T_you = {ch.score:.2f}**")
    elif ch.out_of_time:
        lines.append(f"**out of time**: |K| is still {100 * K / ch.K0:.0f} % of its start at {t:.0f} s")
    return "  \n".join(lines)
