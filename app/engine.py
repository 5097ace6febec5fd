"""One tab's simulation: the scenario, the live run, the changes the GUI asked for, the buffers the plots
and trails read. No viser here: headless tests drive it directly.

Threads: GUI callbacks call ``request_value`` and ``request``, which only record under a lock; the
session's loop thread calls ``tick``, which applies them (each action through ``ACTIONS``) and advances
the run as far as the clock (``app.clock``) allows. The frame (``app.frame``) and the background workers
(``app.workers``: overlay and badge) are mixed in.
"""

from __future__ import annotations

import dataclasses
import io
import math
import threading
import time

import numpy as np

import physics

from . import controls, presets
from .clock import DEFAULT_WARP, FRAME_HZ, Clock
from .frame import Frame, FrameMixin
from .scene import E3, Ring, Shape, align, body_shape
from .workers import BadgeMixin, OverlayMixin

SAMPLES_PER_FRAME = 4  # plot and trail rows per published frame
PLOT_POINTS = 1500  # plot window (ring buffer rows)
TRAIL_POINTS = 1200
HISTORY_ROWS = 20000  # trajectory rows kept for the CSV export
VIEWS = ("inertial", "body")


class Engine(OverlayMixin, BadgeMixin, FrameMixin):
    """The simulation of one tab."""

    def __init__(self, scenario: physics.Scenario | None = None, preset: str = presets.DEFAULT, mesh=None):
        self._lock = threading.Lock()
        self._pending: dict = {}
        self._actions: list[str] = []
        self.change_seq = 0  # bumped by every GUI change
        self.applied_seq = 0  # the last change applied by tick
        self.change_times: dict[int, float] = {}
        self.playing = True
        self.restart_on_change = False
        self.view = "inertial"
        self.exaggeration = 10.0
        self.bob: int | None = None  # plane pendulum the pendulum sliders edit (0-based); None = every bob
        self.show_polhode = False
        self._init_badge()
        self._init_overlay()
        self.error = ""
        self.clock = Clock()
        self.frames = 0
        self.seq = 0
        self.wall_total = 0.0  # wall seconds spent in advance()
        self.scene_changed = True  # the session redraws the static parts (shape, parts) when set
        self.sliders_changed = True  # the session pushes slider values/ranges when set
        self.plots_changed = True
        self.mesh = mesh  # app.mesh.BodyMesh drawn instead of the uniform shape, until a preset is loaded
        name = "from file" if scenario is not None else preset
        if mesh is not None:
            name = f"mesh {mesh.name}"
        self._load(scenario or presets.load_preset(preset), name)

    # ---- requests from GUI callbacks (any thread) -------------------------------------------
    def request_value(self, key: str, value) -> int:
        """A slider's new value. Pendulum sliders edit the bob chosen with the "bob" action."""
        if key.startswith("pendulum.") and self.bob is not None and self.scenario.system == "plane_pendulums":
            key = f"{key}#{self.bob}"
        with self._lock:
            self._pending[key] = value
            return self._bump()

    def request(self, action: str, value=None) -> int:
        """Actions: play, pause, step, reset, warp, preset, system, fidelity, restart_on_change,
        view, exaggeration, overlay, tune."""
        with self._lock:
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
        self.base = sc
        self.preset = name
        self.changes: dict = {}
        self.bob = None
        self.values = controls.values_of(sc)
        self.run = run
        self.clock.warp = DEFAULT_WARP if name == presets.DEFAULT else presets.suggested_warp(sc)
        self.fidelity_choice = sc.run.fidelity
        self._restarted()

    def _restarted(self) -> None:
        """Buffers and reference directions for a run that starts now (or was retuned)."""
        self.plot = Ring(PLOT_POINTS, 4)
        self.trail = Ring(TRAIL_POINTS, 3)
        self.polhode = Ring(TRAIL_POINTS, 3)
        self.history = Ring(HISTORY_ROWS, len(self.run.last.columns))
        self.history_columns = self.run.last.columns
        self.shape = self._shape(self.scenario)
        K0 = self.momentum()
        self.world_wxyz = align(K0, E3) if np.linalg.norm(K0) > 0 else np.array([1.0, 0, 0, 0])
        self.K_ref = float(np.linalg.norm(K0)) or 1.0
        self.w_ref = float(np.linalg.norm(self.run.last.omega[0])) or 1.0
        self._record(self.run.last)
        self.overlay = None
        self.overlay_dirty = True
        self.clock.restart()
        self.scene_changed = self.sliders_changed = self.plots_changed = True
        self._drawn = None

    def static_signature(self) -> tuple:
        """What the static meshes depend on; the session redraws them when it changes."""
        sc = self.scenario
        return (self.shape, tuple(self.ellipsoid()), sc.mass.rho if sc.mass else None,
                sc.cavity.a0 if sc.cavity else None, len(sc.plane_pendulums) + (sc.pendulum is not None))

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

    # ---- applying changes (loop thread) -----------------------------------------------------
    def _apply_pending(self) -> None:
        with self._lock:
            pending, self._pending = self._pending, {}
            actions, self._actions = self._actions, []
            seq = self.change_seq
        try:
            for action, value in actions:
                self._act(action, value)
            if pending:
                self._apply_values(pending)
            if actions or pending:
                self.clock.changed()
        except physics.ScenarioError as exc:
            self.error = str(exc)
        except Exception as exc:  # never let a bad input kill the loop
            self.error = f"{type(exc).__name__}: {exc}"
        self.applied_seq = seq

    def _apply_values(self, pending: dict) -> None:
        changes = controls.merge_changes(self.changes, pending)
        sc = controls.apply_changes(self.base, changes)  # ScenarioError leaves everything as it was
        sc = sc.replace(run=_with_fidelity(sc.run, self.fidelity_choice))
        restart = self.restart_on_change or controls.restarts(pending)
        kept = self.run.retune(sc, keep_state=not restart)
        self.changes = changes
        for k, v in pending.items():
            key, _, which = k.partition("#")
            if not isinstance(v, str) and (not which or int(which) == (self.bob or 0)):
                self.values[key] = v
        if sc.pendulum is not None and isinstance(sc.pendulum.k, str):
            self.values["pendulum.k"] = controls.values_of(sc)["pendulum.k"]  # "resonant" resolved: show the k
            self.sliders_changed = True
        self.error = ""
        self.shape = self._shape(sc)
        if self.static_signature() != self._drawn:
            self.scene_changed = True  # redraw the meshes only when what they show has changed
        self.overlay_dirty = True
        if not kept:
            self._restarted()

    # ---- actions (loop thread): one handler each, looked up in ACTIONS ----------------------------
    def _act(self, action: str, value) -> None:
        handler = ACTIONS.get(action)
        if handler is None:
            raise ValueError(f"unknown action {action!r}")
        handler(self, value)

    def _play(self, _value) -> None:
        self.playing = True

    def _pause(self, _value) -> None:
        self.playing = False

    def _step(self, _value) -> None:
        self.playing = False
        self._advance(self.warp / FRAME_HZ)

    def _reset(self, _value) -> None:
        self.run.reset()
        self.error = ""
        self._restarted()

    def _set_warp(self, value) -> None:
        self.clock.set_warp(float(value))

    def _preset(self, value) -> None:
        sc = presets.load_preset(value)
        self.mesh = None  # a preset brings its own body
        self._load(sc, value)
        self.error = ""

    def _system(self, value) -> None:
        if value != self.scenario.system:
            name = next(n for n in presets.preset_names() if presets.load_preset(n).system == value)
            self.mesh = None
            self._load(presets.load_preset(name), name)
            self.error = ""

    def _fidelity(self, value) -> None:
        sc = self.scenario.replace(run=_with_fidelity(self.scenario.run, value))
        self.run.retune(sc, keep_state=False)
        self.fidelity_choice = value
        self.error = ""
        self._restarted()

    def _restart_on_change(self, value) -> None:
        self.restart_on_change = bool(value)

    def _view(self, value) -> None:
        self.view = value if value in VIEWS else "inertial"
        self.trail.clear()  # the trail means something else in the other frame
        self.scene_changed = True

    def _exaggeration(self, value) -> None:
        self.exaggeration = float(value)

    def _overlay(self, value) -> None:
        self.overlay_fidelity = value
        self.overlay_dirty = True
        self.plots_changed = True

    def _tune(self, _value) -> None:
        self._apply_values({"pendulum.k": "resonant"})

    def _bob(self, value) -> None:
        n = len(self.scenario.plane_pendulums)
        self.bob = None if value in (None, "all") or n == 0 else min(max(int(value), 0), n - 1)
        self.values.update({k: v for k, v in controls.values_of(self.scenario, self.bob).items()
                            if k.startswith("pendulum.")})
        self.sliders_changed = True

    def _polhode(self, value) -> None:
        self.show_polhode = bool(value)
        self.polhode.clear()

    def _mesh(self, value) -> None:
        self._use_mesh(value)

    def _upload(self, value) -> None:
        """(file name, bytes) from the browser: through the parser, size-capped."""
        from .upload import display_name, parse_upload

        name, content = value
        sc = parse_upload(name, content)
        self.mesh = None
        self._load(sc, f"upload {display_name(name)}")
        self.error = ""

    def _scenario(self, value) -> None:
        """(Scenario, label) from a panel: a sweep's point, a recommended method."""
        sc, label = value
        self.mesh = None
        self._load(sc, label)
        self.error = ""

    def _use_mesh(self, name: str) -> None:
        """Draw the body as a mesh from assets/meshes, or as the uniform shape of its inertia again
        ("inertia shape"). The mesh, a uniform solid of mass M scaled to keep A + B + C, gives A, B, C."""
        from . import mesh as meshes

        if name in (None, "", meshes.INERTIA_SHAPE):
            self.mesh = None
            self.shape = self._shape(self.scenario)
            self.scene_changed = True
            return
        path = meshes.asset_path(name)  # only names the assets folder holds: no path comes from a browser
        body = meshes.scaled_to(meshes.load_mesh(path, self.scenario.body.M), self.scenario.body)
        sc = meshes.with_mesh(self.scenario, body)
        self.mesh = body
        self._load(sc, f"mesh {name}")


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
        if self.playing:
            t0 = self.run.t
            wall = self.clock.frame_wall(wall_dt)
            self._advance(self.warp * wall, floor=wall)
            self.clock.played(self.run.t - t0, wall)
        if self.overlay is not None and self.run.t > self.overlay[0][-1]:
            self.overlay_dirty = True  # the run has passed the prediction: predict again from now
        if self.overlay_dirty:
            self._compute_overlay()
        self.frames += 1
        return self.frame()

    def _advance(self, dt: float, floor: float | None = None) -> None:
        """Integrate dt simulated seconds. With a ``floor`` (a frame's wall seconds: playing), only as many
        as TICK_BUDGET_S of wall time affords at the last measured rate (PROBE times fewer after a change,
        whose cost is not known yet), but never less than real time."""
        if self.run.ended or dt <= 0:
            return
        if floor is not None:
            dt = self.clock.allowance(dt, floor)
        t0, start = self.run.t, time.perf_counter()
        try:
            tr = self.run.advance(dt, samples=SAMPLES_PER_FRAME)
        except Exception as exc:  # a model error that is not an integrator status: report, stop
            self.run.status, self.run.message = "fault", f"{type(exc).__name__}: {exc}"
            return
        spent = time.perf_counter() - start
        self.wall_total += spent
        self.clock.measured(self.run.t - t0, spent)
        if len(tr):
            self._record(tr)

    def _record(self, tr: physics.Trajectory) -> None:
        self.plot.extend(np.column_stack([tr.t, tr.theta, tr.K, tr.E]))
        if tr.columns == self.history_columns:
            self.history.extend(tr.table())
        for q in tr.quat:
            self.trail.extend(self._trail_point(q))
        if self.show_polhode:
            self.polhode.extend(self._polhode_points(tr.omega))
        self.plots_changed = True

    def plot_window(self) -> float:
        """Simulated seconds the plots show at the present warp."""
        return PLOT_POINTS / (SAMPLES_PER_FRAME * FRAME_HZ) * self.warp

    # ---- output ----------------------------------------------------------------------------------
    def plot_data(self) -> tuple[np.ndarray, ...]:
        """(t, theta, overlay's theta, |K|, E) over the plot window. The overlay starts from the state at
        the time it was computed, so before that time it equals theta; without an overlay it is theta
        (the plot hides it). No NaN: uPlot's auto-range would break on them."""
        rows = self.plot.values()
        t = rows[:, 0]
        over = rows[:, 1].copy()
        if self.overlay is not None and len(t):
            ot, oth = self.overlay
            after = t >= ot[0]
            over[after] = np.interp(t[after], ot, oth)
        return t, rows[:, 1], over, rows[:, 2], rows[:, 3]

    def readouts(self) -> dict[str, str]:
        run = self.run
        d = {"t": f"{run.t:.4g} s", "theta": f"{run.last.theta[0]:.6f} rad", "|K|": f"{run.last.K[0]:.6g} kg m^2/s",
             "E": f"{run.last.E[0]:.6g} J"}
        T = physics.derived(self.scenario)["T"] if run.b > 0 else math.inf
        d["T"] = "no braking" if math.isinf(T) else f"{T:.6g} s"
        rem = run.remaining_braking_time()
        d["remaining"] = "n/a" if math.isinf(rem) else f"{rem:.6g} s"
        d["fidelity"] = f"{run.fidelity} ({run.model.name})" + (" by auto" if run.requested == "auto" else "")
        q = run.last.quat[0]
        d["q"] = "[" + ", ".join(f"{x:.4f}" for x in q) + "]"
        return d

    def csv(self) -> bytes:
        buf = io.StringIO()
        np.savetxt(buf, self.history.values(), delimiter=",", header=",".join(self.history_columns), comments="",
                   fmt="%.17g")
        return buf.getvalue().encode()

    def toml(self) -> bytes:
        return self.scenario.to_toml().encode()


# action name -> handler; ``Engine.request(name, value)`` queues one, ``tick`` applies it
ACTIONS = {
    "play": Engine._play, "pause": Engine._pause, "step": Engine._step, "reset": Engine._reset,
    "warp": Engine._set_warp, "preset": Engine._preset, "system": Engine._system, "fidelity": Engine._fidelity,
    "restart_on_change": Engine._restart_on_change, "view": Engine._view, "exaggeration": Engine._exaggeration,
    "overlay": Engine._overlay, "tune": Engine._tune, "bob": Engine._bob, "polhode": Engine._polhode,
    "mesh": Engine._mesh, "upload": Engine._upload, "scenario": Engine._scenario,
}


def _with_fidelity(run: physics.Run, fidelity: str) -> physics.Run:
    return dataclasses.replace(run, fidelity=fidelity)
