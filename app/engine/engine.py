"""One tab's simulation: the scenario, the live run, the changes the GUI asked for, the buffers the plots
and trails read. No viser here: headless tests drive it directly.

Threads: GUI callbacks call ``request_value`` and ``request``, which only record under a lock; the
session's loop thread calls ``tick``, which applies them (each action through ``ACTIONS``) and advances
the run as far as the clock (``app.engine.clock``) allows. The engine holds its collaborators and hands each
what it reads: the background workers are objects with their own state (``prediction``, an
``app.engine.workers.Overlay``; ``auto_badge``, a ``Badge``); the actions (``app.engine.actions.act``), what the
panel reads out and exports (``app.engine.output``) and the frame (``app.engine.frame``) are functions, called by
the engine's methods of the same names.
"""

from __future__ import annotations

import dataclasses
import threading
import time

import numpy as np

import physics

from . import challenge, controls, edits, output, presets, words
from . import frame as frames
from .actions import act, choices_of, system_actions, with_choices
from .buffers import (
    EDITS_LISTED,
    HISTORY_ROWS,
    PENDING_EACH,
    PLOT_POINTS,
    RECENT,
    RETUNES_KEPT,
    SAMPLES_PER_FRAME,
    TRAIL_POINTS,
    VIEWS,
    WHOLE_RUN,
    WHOLE_RUN_POINTS,
)
from .clock import DEFAULT_WARP, FRAME_HZ, Clock
from .compare import restart_compare
from .frame import Frame
from .geometry import E3, Ring, Shape, align, body_shape
from .history import DecimatingStore
from .sphere import MomentumPath
from .trail import split_advance, thinned
from .trail import turn_period as cone_turn_period
from .workers import Badge, Overlay


class Engine:
    """The simulation of one tab."""

    def __init__(self, scenario: physics.Scenario | None = None, preset: str = presets.DEFAULT, mesh=None):
        self._lock = threading.Lock()
        self._chosen: tuple | None = None  # (base, choices, the base with them): see _chosen_base
        self._pending: dict = {}
        self._actions: list[str] = []
        self.change_seq = 0  # bumped by every GUI change
        self.applied_seq = 0  # the last change applied by tick
        self.change_times: dict[int, float] = {}
        self.value_requested_at = float("-inf")  # time.monotonic() of the last slider value requested
        self.playing = True
        self.restart_on_change = False
        self.view = "inertial"
        self.view_values: dict[str, float] = {}  # physics.figure.View's fields a system's view action set
        self.choices: dict[str, str] = {}  # a system's choice actions: scenario key -> option, kept across scenes
        self.item: int | None = None  # the item of an array table the sliders edit (0-based); None = every item
        self.show_polhode = False
        self.show_sphere = True  # the momentum sphere beside the body (app.scene.sphere_view)
        self.sphere_path = MomentumPath()  # K's direction in body axes over the run (app.engine.sphere)
        self.auto_badge = Badge(lambda: self.scenario)  # auto's choice in words, worked out off the loop thread
        self.prediction = Overlay(self._plots_changed, self._fail)  # the cheaper model's, off the loop thread
        self.error = ""
        self.upload_note: tuple[str, str] | None = None  # ("loaded" or "refused", words): beside the upload button
        self.guard = edits.Guard()  # typed values judged, notes beside sliders, undo (app.engine.edits)
        self.clock = Clock()
        self._last_frame: Frame | None = None  # shown again, as a fault, if a state cannot be observed
        self.frames = 0
        self.seq = 0
        self.wall_total = 0.0  # wall seconds spent in advance()
        self.scene_changed = True  # the session redraws the static parts (shape, parts) when set
        self.sliders_changed = True  # the session pushes slider values/ranges when set
        self.plots_changed = True
        self.plot_span = WHOLE_RUN
        self.mesh = mesh  # app.engine.mesh.BodyMesh drawn instead of the uniform shape, until a preset is loaded
        self.compare = None  # app.engine.compare.Comparison: a second run with one difference, on the same clock
        self.challenge = None  # app.engine.challenge.Challenge: the braking challenge's attempt, when one runs
        name = "from file" if scenario is not None else preset
        if mesh is not None:
            name = f"mesh {mesh.name}"
        self._load(scenario or presets.load_preset(preset), name)

    # ---- requests from GUI callbacks (any thread) -------------------------------------------
    def request_value(self, key: str, value, text: str | None = None) -> int:
        """A slider's new value; ``text``: what the user typed into its box (app.engine.typed read it), None for the
        slider's own move. A slider of an array table edits the item an "item" action chose."""
        slider = key
        key = controls.item_key(key, self.scenario.system, self.item)  # one item chosen: that item
        with self._lock:
            self.guard.received(slider, value, text)
            self._pending[key] = value
            self.value_requested_at = time.monotonic()  # app.panel.playbar drops a keyed step a focused slider took
            return self._bump()

    def refuse_typed(self, key: str, text: str, why: str) -> None:
        """A text typed into ``key``'s box that is no number (``why``): said beside the slider, nothing applied."""
        with self._lock:
            self.guard.unreadable(key, text, why, self.values.get(key))

    def request(self, action: str, value=None) -> int:
        """Actions: play, pause, step, reset, warp, preset, system, fidelity, restart_on_change,
        view, overlay, ... (app.engine.actions.ACTIONS), and each system's own by name (physics.figure.Action)."""
        with self._lock:
            if sum(a == action for a, _ in self._actions) >= PENDING_EACH:
                # more than a person clicks (a held button repeats 10 times a second) between two ticks is a
                # client flooding: the latest requests are the ones that count
                first = next(i for i, (a, _) in enumerate(self._actions) if a == action)
                del self._actions[first]
            self._actions.append((action, value))
            return self._bump()

    def _bump(self) -> int:
        self.change_seq += 1
        self.change_times[self.change_seq] = time.perf_counter()
        if len(self.change_times) > 1000:
            for k in sorted(self.change_times)[:500]:
                del self.change_times[k]
        return self.change_seq

    # ---- loading ---------------------------------------------------------------------------
    def _load(self, sc: physics.Scenario, name: str) -> None:
        run = physics.LiveRun(sc)  # raises ScenarioError before anything changes
        challenge.stop(self)  # another scene ends a braking challenge's attempt
        self.guard.forget(sc, name)
        self.base = sc
        self.preset = name
        self.changes: dict = {}
        self.item = None
        self.values = controls.values_of(sc)
        self.run = run
        self.clock.warp = DEFAULT_WARP if name == presets.DEFAULT else presets.suggested_warp(sc)
        self._adopt_choices(sc)
        self._restarted()
        self.view_values.update(self.initial_view())  # the panel's slider follows (sliders_changed)

    def _adopt_choices(self, sc: physics.Scenario) -> None:
        """The panel's run-level choices (kept across slider edits, actions.with_choices) as ``sc`` has them."""
        self.fidelity_choice, self.accuracy_choice = sc.run.fidelity, sc.run.accuracy
        self.choices = choices_of(sc, self.choices)

    def initial_view(self) -> dict[str, float]:
        """The values the scene's view actions start with (the displacement's factor that keeps a moving part
        within the body): each action's ``initial``, from the body's drawn size and its angular velocity now."""
        sc = self.scenario
        omega = self.run.last.omega[0]
        return {a.key: float(a.initial(sc, self.shape.extent, omega)) for a in system_actions(sc, "view")
                if a.initial is not None and a.shown(sc)}

    def __getattr__(self, name: str):
        """A View field by its name (``engine.exaggeration``) and a choice action's option by the action's name
        (``engine.pivot_choice``): the names come from physics, not from here."""
        if name.startswith("_") or name in ("view_values", "choices"):
            raise AttributeError(name)
        if name in physics.figure.View.__dataclass_fields__:
            return self.view_values.get(name, physics.figure.View.__dataclass_fields__[name].default)
        if name.endswith("_choice"):
            for a in system_actions(None, "choice"):
                if a.name == name[: -len("_choice")]:
                    return self.choices.get(a.key, a.options[0])
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def _restarted(self) -> None:
        """Buffers and reference directions for a run that starts now (or was retuned)."""
        self.plot = Ring(PLOT_POINTS, 4)
        self.trail = Ring(TRAIL_POINTS, 3)
        self.polhode = Ring(TRAIL_POINTS, 3)
        self.sphere_path.clear()
        self.plot_all = DecimatingStore(WHOLE_RUN_POINTS, 4)
        self.history = DecimatingStore(HISTORY_ROWS, len(self.run.last.columns))
        self.history_columns = self.run.last.columns
        self.start_scenario = self.scenario  # what the run began from at t = 0 (the overlay predicts from it)
        self.edits: list[tuple[float, str]] = []  # (t, what) of the first changes the run went on through
        self.retunes: list[tuple[float, physics.Scenario]] = []  # (t, scenario) of every change the run went on
        # through, for a replay of this run (app.replay.record); None once more than RETUNES_KEPT
        self.edit_count = 0
        self.shape = self._shape(self.scenario)
        K0 = self.momentum()
        self.world_wxyz = align(K0, E3) if np.linalg.norm(K0) > 0 else np.array([1.0, 0, 0, 0])
        self.K_ref = float(np.linalg.norm(K0)) or 1.0
        self.w_ref = float(np.linalg.norm(self.run.last.omega[0])) or 1.0
        self._record(self.run.last)
        self.prediction.restart()
        self.clock.restart()
        self.guard.epoch += 1  # buffers start anew: an undo to before this cannot rewind them
        self.scene_changed = self.sliders_changed = self.plots_changed = True
        self._drawn = None
        self.edit_dE: float | None = None  # what the last edit did to E (J), shown until the next edit or reset
        self.edit_note = ""  # why the last edit could not keep the state
        restart_compare(self)  # the second run (compare mode) starts again with the first

    # ---- the background workers (app.engine.workers) ------------------------------------------------
    def _plots_changed(self) -> None:
        self.plots_changed = True

    def _fail(self, message: str) -> None:
        self.error = message

    @property
    def overlay(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The cheaper model's prediction (t, theta) from t = 0, or None (``Overlay.curve``)."""
        return self.prediction.curve

    @property
    def overlay_fidelity(self) -> str:
        return self.prediction.fidelity

    @property
    def has_overlay(self) -> bool:
        return self.prediction.curve is not None

    def overlay_title(self) -> str:
        """The prediction chart's title (``Overlay.title``)."""
        return self.prediction.title(self.start_scenario, self.edits, self.edit_count)

    def wait_overlay(self, timeout: float = 30.0) -> bool:
        """Block until the overlay being computed is done (for tests and scripts)."""
        return self.prediction.wait(timeout)

    def cancel_workers(self) -> None:
        """The tab closed: a prediction being computed gives up at its next chunk, and the badge's analysis
        stops, so nothing of a closed tab keeps a core busy."""
        self.prediction.cancel()
        self.auto_badge.cancel()

    def badge(self, block: bool = False) -> str:
        """Auto's badge as markdown (``Badge.text``): a placeholder until its worker is done, unless ``block``."""
        return self.auto_badge.text(block)

    def badge_details(self) -> str:
        """The badge's conditions as formulas (``Badge.details``); "" until the badge is ready."""
        return self.auto_badge.details()

    # ---- the frame (app.engine.frame) ---------------------------------------------------------------
    def frame(self) -> Frame:
        """What the next published frame shows, from the run's last state."""
        self.seq += 1
        return frames.make_frame(self.run, seq=self.seq, applied=self.applied_seq, view=self.view,
                                 world_wxyz=self.world_wxyz, K_ref=self.K_ref, w_ref=self.w_ref,
                                 extent=self.shape.extent, view_values=self.view_values, trail=self.trail.values(),
                                 polhode=self.polhode.values() if self.show_polhode else None)

    def frame_figure(self) -> tuple:
        """The system's picture of the run's last state (physics.figure primitives, body frame, m)."""
        return frames.figure(self.run, self.shape.extent, self.view_values)

    def ellipsoid(self) -> np.ndarray:
        """The drawn inertia ellipsoid's semi-axes (m)."""
        return frames.ellipsoid(self.scenario.body, self.shape.extent)

    def momentum(self) -> np.ndarray:
        """Inertial total angular momentum now (kg m^2/s); a closed form's is fixed along its start's G, turned
        by where an edit restarted it (physics.LiveRun.momentum)."""
        return self.run.momentum()

    def _trail_point(self, q: np.ndarray) -> np.ndarray:
        """Inertial view: the tip of the symmetry axis; body view: the direction of K in the body."""
        return frames.trail_point(q, self.view, self.world_wxyz, self.momentum())

    def static_signature(self) -> tuple:
        """What the static meshes depend on: the body, its ellipsoid and the system's figure's static part with
        the names of its moving part (one drawn object per name); the session redraws them when it changes."""
        parts = self.frame_figure()
        static = tuple(p for p in parts if not p.moves)
        return (self.shape, tuple(self.ellipsoid()), static, tuple(p.name for p in parts if p.moves))

    def mark_drawn(self) -> None:
        self._drawn = self.static_signature()

    def _shape(self, sc: physics.Scenario) -> Shape:
        if self.mesh is not None:
            v = self.mesh.vertices
            return Shape("mesh", dims=tuple(float(x) for x in v.max(axis=0) - v.min(axis=0)))
        return body_shape(sc.body.A, sc.body.B, sc.body.C, sc.body.M)

    @property
    def scenario(self) -> physics.Scenario:
        return self.run.scenario

    @property
    def edited(self) -> bool:
        """Whether the scene differs from the preset loaded (a slider, tuning, the fidelity, auto's accuracy, the
        pivot): the panel then names the preset "(edited)", so choosing the preset again is a change that reloads it."""
        return (bool(self.changes) or self.fidelity_choice != self.base.run.fidelity
                or self.accuracy_choice != self.base.run.accuracy
                or self.choices != choices_of(self.base, self.choices))

    # ---- applying changes (loop thread) -----------------------------------------------------
    def _apply_pending(self) -> None:
        with self._lock:
            pending, self._pending = self._pending, {}
            actions, self._actions = self._actions, []
            seq = self.change_seq
        try:
            for action, value in actions:
                act(self, action, value)
                self.guard.interrupt()  # a value after an action starts a new change
            self._apply_guarded(pending)
            if actions or pending:
                self.clock.changed()
        except physics.ScenarioError as exc:
            self.error = str(exc)
        except ValueError as exc:  # an action's value refused in its own words (they name it and what is allowed)
            self.error = str(exc) or type(exc).__name__
        except Exception as exc:  # never let a bad input kill the loop
            self.error = f"{type(exc).__name__}: {exc}"
        self.applied_seq = seq

    def _apply_guarded(self, pending: dict) -> None:
        """Slider values through the guard (app.engine.edits): a value physics rejects is not applied and its
        slider goes back to the last good value; one beyond the slider's usual span is applied and the span
        widens; each change is saved for undo first."""
        guard = self.guard
        if not pending:
            return
        accepted = guard.screen(self._chosen_base(), self.changes, pending, self.values)
        if accepted:
            saved = guard.before_change(accepted, self)
            try:
                self._apply_values(accepted, guard.screened)
            except Exception as exc:
                guard.failed(accepted, saved, self.values, exc)
                raise
        if guard.rejections:
            self.error = guard.rejections[-1]  # shown beside the slider (the panel omits it at the top)

    def _chosen_base(self) -> physics.Scenario:
        """The scene as loaded with the panel's run-level choices: what slider changes apply to. Built again
        only when the base or a choice changes, so that a slider change builds and validates its scenario
        once (the screen's build is the one applied)."""
        choices = (self.fidelity_choice, self.accuracy_choice, dict(self.choices))
        if self._chosen is None or self._chosen[0] is not self.base or self._chosen[1] != choices:
            self._chosen = (self.base, choices, with_choices(self.base, *choices))
        return self._chosen[2]

    def _apply_values(self, pending: dict, sc: physics.Scenario | None = None) -> None:
        """Apply slider values; ``sc``: the scenario they make, when the screen has built it already."""
        challenge.stop(self)  # a parameter changed: the race is no longer the level's
        changes = controls.merge_changes(self.changes, pending)
        if sc is None:
            sc = controls.apply_changes(self._chosen_base(), changes)  # ScenarioError leaves everything as it was
        sc = with_choices(sc, self.fidelity_choice, self.accuracy_choice, self.choices)  # a part a change added
        restart = self.restart_on_change or controls.restarts(pending)
        kept = self.run.retune(sc, keep_state=not restart)
        self.changes = changes
        for k, v in pending.items():
            key, _, which = k.partition("#")
            if edits.is_number(v) and (not which or int(which) == (self.item or 0)):
                p = controls.BY_KEY.get(key)
                if p is not None and controls.slider_range(p, v) != controls.slider_range(p, self.values[key]):
                    self.sliders_changed = True  # the slider's span widens to show the value (or narrows back)
                self.values[key] = v
        # a value given in words ("resonant") or none (body.B = None, an axisymmetric body): its slider shows what
        # the scenario resolves it to
        worded = [k.partition("#")[0] for k, v in changes.items() if not edits.is_number(v)]
        if worded:
            resolved = controls.values_of(sc, self.item)
            self.values.update({k: resolved[k] for k in worded if k in resolved})
            self.sliders_changed = True
        self.error = ""
        self.shape = self._shape(sc)
        if self.static_signature() != self._drawn:
            self.scene_changed = True  # redraw the meshes only when what they show has changed
        self.prediction.dirty = True
        if kept:  # the run goes on under other parameters: the plots and the export say so
            self.log_retune(sc)
            self.edit_count += 1
            if len(self.edits) < EDITS_LISTED:
                item = [a.label for a in system_actions(sc, "item")][:1]
                self.edits.append((self.run.t, _edit_names(pending, *item)))
        if not kept:
            self._restarted()
        self._note_edit(kept)

    def log_retune(self, sc: physics.Scenario) -> None:
        """Keep (t, scenario) of a change the run went on through, so that a replay can make it at the same t."""
        if self.retunes is not None:
            self.retunes = self.retunes + [(float(self.run.t), sc)] if len(self.retunes) < RETUNES_KEPT else None

    def replay_retune(self, sc: physics.Scenario) -> None:
        """Go on under ``sc`` from now, as a change made in a tab did (app.replay.record replays a tab's run)."""
        kept = self.run.retune(sc, keep_state=True)
        self._adopt_choices(sc)
        self.shape = self._shape(sc)
        self.scene_changed = self.prediction.dirty = True
        if not kept:
            self._restarted()

    def _note_edit(self, kept: bool) -> None:
        """Remember what the edit just applied did: the change of E when the state was carried (K and the
        attitude kept, physics.carry_state), or why it restarted instead (a closed form has no state)."""
        self.edit_dE = self.run.energy_change if kept else None
        self.edit_note = self.run.edit_note
        if kept:  # the new state's row, at the same t: the plots show E's step, and the readouts refresh
            self._record(self.run.last)
            if self.compare is not None:
                self.compare.follow(self)  # the same edit, the difference kept (app.engine.compare)

    # ---- the clock's figures, as attributes (scripts and tests set eng.warp) --------------------
    @property
    def warp(self) -> float:
        return self.clock.warp

    @warp.setter
    def warp(self, value: float) -> None:
        self.clock.warp = float(value)

    @property
    def achieved_warp(self) -> float:
        return self.clock.achieved_warp

    # ---- stepping ----------------------------------------------------------------------------
    def tick(self, wall_dt: float) -> Frame:
        """Apply pending changes, advance by warp * wall_dt (if playing) and return the frame."""
        self._apply_pending()
        challenge.before_advance(self)  # a thruster not pressed again stops
        if self.playing:
            t0 = self.run.t
            wall = self.clock.frame_wall(wall_dt)
            tap = challenge.tap_seconds(self)
            if tap is not None and tap < self.warp * wall:  # a tap fires as long as it was held, then stops
                self._advance(tap)
                self._advance(self.warp * wall - tap, floor=wall - tap / self.warp)
            else:
                self._advance(self.warp * wall, floor=wall)
            self.clock.played(self.run.t - t0, max(wall_dt, 0.0))  # the wall time that passed, unclipped
        else:
            self.clock.paused()
        curve = self.prediction.curve
        if curve is not None and self.run.t > curve[0][-1]:
            self.prediction.dirty = True  # the run has passed the prediction: predict again from now
        if self.prediction.dirty:
            self.prediction.compute(self.start_scenario, self.run.t, self.plot_window())
        self.frames += 1
        try:
            fr = self.frame()
        except Exception as exc:  # a state the model cannot even observe (extreme values): a fault, never a crash
            self.run.status = "fault"
            self.run.message = f"the state cannot be shown ({type(exc).__name__}: {str(exc)[:120]}); undo or reset"
            if self._last_frame is None:
                raise
            fr = dataclasses.replace(self._last_frame, status=self.run.status, message=self.run.message,
                                     applied=self.applied_seq)
        self._last_frame = fr
        return fr

    def _advance(self, dt: float, floor: float | None = None) -> None:
        """Integrate dt simulated seconds. With a ``floor`` (a frame's wall seconds: playing), only as many
        as TICK_BUDGET_S of wall time affords at the last measured rate (PROBE times fewer after a change,
        whose cost is not known yet), but never less than real time."""
        if dt <= 0 or (self.run.ended and self.compare is None):
            return
        if floor is not None:
            dt = self.clock.allowance(dt, floor)
        t0, start = self.run.t, time.perf_counter()
        if self.compare is not None:  # the same simulated dt, timed with this run's: the budget counts both
            self.compare.advance(dt)
            if self.run.ended:  # this run braked or faulted: the second goes on alone
                return
        # beyond a few samples per turn of the cone, the frame's last turns are sampled densely for the trail
        head, tail, tail_samples = split_advance(dt, SAMPLES_PER_FRAME, self.turn_period())
        dense = None
        try:
            tr = self.run.advance(head, samples=SAMPLES_PER_FRAME - 1 if tail > 0 else SAMPLES_PER_FRAME
                                  ) if head > 0 else None
            if tail > 0 and not self.run.ended:
                dense = self.run.advance(tail, samples=tail_samples)
        except Exception as exc:  # a model error that is not an integrator status: report, stop
            self.run.status, self.run.message = "fault", f"{type(exc).__name__}: {exc}"
            return
        spent = time.perf_counter() - start
        self.wall_total += spent
        self.clock.measured(self.run.t - t0, spent)
        if tr is not None and len(tr):
            self._record(tr, trail_too=dense is None or not len(dense))
        if dense is not None and len(dense):
            self.trail.clear()  # the trail is the last turns alone: older samples are too far apart to join
            self._extend_trail(dense)
            self._record(thinned(dense, 1 if tr is not None else SAMPLES_PER_FRAME), trail_too=False)
        if self.challenge is not None:  # stopped or out of time: the attempt ends
            rows = self.plot.values()
            challenge.after_advance(self, rows[rows[:, 0] > t0], self.run.t - t0)

    def turn_period(self) -> float:
        """Seconds the trail's point takes to go once round the cone, at the fastest (app.engine.trail)."""
        b, last = self.scenario.body, self.run.last
        return cone_turn_period(b.A, b.B, float(last.K[0]), float(np.linalg.norm(last.omega[0])))

    def _extend_trail(self, tr: physics.Trajectory) -> None:
        K = self.momentum()  # once a frame: the model's invariants cost more than the turns below
        self.trail.extend(frames.trail_points(tr.quat, self.view, self.world_wxyz, K))
        self.sphere_path.extend(tr.quat, K)  # the same samples: a path that joins up at any warp

    def _record(self, tr: physics.Trajectory, trail_too: bool = True) -> None:
        rows = np.column_stack([tr.t, tr.theta, tr.K, tr.E])
        self.plot.extend(rows)
        self.plot_all.extend(rows)
        if tr.columns == self.history_columns:
            self.history.extend(tr.table())
        if trail_too:
            self._extend_trail(tr)
        if self.show_polhode:
            self.polhode.extend(frames.polhode_points(self.scenario.body, self.shape.extent, tr.omega))
        self.plots_changed = True

    # ---- output: the plots' data, the readouts, the exports (app.engine.output) ------------------------
    def plot_data(self, span: str | None = None) -> tuple[np.ndarray, ...]:
        """(t, theta, overlay's theta, |K|, E) over the run from t = 0 (``WHOLE_RUN``, thinned to at most
        WHOLE_RUN_POINTS + 1 rows) or the last PLOT_POINTS rows (``RECENT``); ``span`` defaults to the
        one the panel chose (``output.plot_data``)."""
        rows = (self.plot if (span or self.plot_span) == RECENT else self.plot_all).values()
        return output.plot_data(rows, self.overlay)

    def readouts(self) -> dict[str, str]:
        """What the panel shows, ``name -> value`` (``output.readouts``, then ``output.end_readouts``)."""
        d = output.readouts(self.run, self.world_wxyz, self.edit_dE, self.edit_note)
        d.update(output.end_readouts(self.end_state(), float(self.run.last.E[0])))
        return d

    def start_note(self) -> str:
        """The theta(0) and |K(0)| the run started from, where they differ from the Initial state sliders, and why
        (``words.start_words``); "" otherwise."""
        rows = self.plot_all.values()
        if not len(rows) or rows[0, 0] != 0.0:
            return ""
        return words.start_words(self.start_scenario, float(rows[0, 1]), float(rows[0, 2]))

    def once_per_frame(self, name: str, compute):
        """``compute()``: a value every view of this frame reads alike. One tab has one view, so it is computed
        where asked; a class's views share one (app.serve.class_view.EngineView keeps it for the frame)."""
        return compute()

    def details(self) -> dict[str, str]:
        """The model and the raw attitude, and the end state in words, for the Details folder (``output.details``)."""
        return {**output.details(self.run), **output.end_details(self.end_state())}

    def end_state(self, block: bool = False):
        """Where the energy sink leads from the run's K now (physics.end_state): an EndState, or a NoEndState
        with its reason. Worked out again only when the scene or |K| changes: a minimisation over the part's
        coordinates (up to 0.6 s for the moving mass), so in a background thread, the frames going on meanwhile;
        until it is ready, a NoEndState whose reason is ``output.END_PENDING``. ``block``: wait for it instead.
        Under braking or a medium |K| changes every frame and the answer (none) is at once."""
        sc, K = self.scenario, self.momentum()
        G = float(np.linalg.norm(K))
        cached = getattr(self, "_end", None)
        if cached is not None and cached[0] is sc and abs(cached[1] - G) <= 1e-9 * max(G, 1e-300):
            return cached[2]
        direction = self.sphere_path.now  # K in body axes now: the side of the axis it ends on
        K_body = None if direction is None else G * direction
        if block or any(physics.brake_and_medium(sc)):
            self._end = (sc, G, _end_state(sc, K_body))
            return self._end[2]
        if not getattr(self, "_end_busy", False):
            self._end_busy = True
            threading.Thread(target=self._end_work, args=(sc, G, K_body), name="end state", daemon=True).start()
        return physics.NoEndState(output.END_PENDING)

    def _end_work(self, sc: physics.Scenario, G: float, K_body) -> None:
        try:
            self._end = (sc, G, _end_state(sc, K_body))
            # the panel redraws readouts and plots only when told: a paused run would say "working it out..."
            # until the next edit
            self.plots_changed = True
        finally:
            self._end_busy = False  # the next call starts another if the scene or |K| has changed since

    def csv(self) -> bytes:
        """The run from t = 0 as CSV (``output.csv``)."""
        return output.csv(self.history, self.history_columns, self.preset, self.run.t, self.edits_text())

    def edits_text(self) -> str:
        """The changes the run went on through since t = 0 ("" when none)."""
        return output.edits_text(self.edits, self.edit_count)

    def toml(self) -> bytes:
        return self.scenario.to_toml().encode()

    def plot_window(self) -> float:
        """Simulated seconds the plots show at the present warp."""
        return PLOT_POINTS / (SAMPLES_PER_FRAME * FRAME_HZ) * self.warp


def _end_state(sc: physics.Scenario, K_body):
    """physics.end_state, a failure turned into its reason (the loop and the panel must go on)."""
    try:
        return physics.end_state(sc, K=K_body)
    except (physics.ScenarioError, ArithmeticError, ValueError) as exc:
        return physics.NoEndState(f"not worked out: {exc}")


def _edit_names(pending: dict, item: str = "item") -> str:
    """The sliders a change moved, by their labels ("m (kg)"; with ``item`` the item action's label, "l (m) of
    bob 2")."""
    names = []
    for k in sorted(pending):
        key, _, which = k.partition("#")
        p = controls.BY_KEY.get(key)
        names.append((p.label if p is not None else key) + (f" of {item} {int(which) + 1}" if which else ""))
    return ", ".join(names)


__all__ = ["EDITS_LISTED", "HISTORY_ROWS", "PLOT_POINTS", "RECENT", "SAMPLES_PER_FRAME", "TRAIL_POINTS", "VIEWS",
           "WHOLE_RUN", "WHOLE_RUN_POINTS", "Engine", "Frame"]
