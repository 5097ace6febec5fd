"""One tab's simulation state: the scenario, the live run, pending GUI changes, ring buffers, and the
Frame of numbers the scene and the panel show. No viser here: headless tests drive it directly.

Threads: GUI callbacks call the ``request_*`` methods, which only record values under a lock; the
session's loop thread calls ``tick``, which applies them and advances the run.
"""

from __future__ import annotations

import io
import math
import threading
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

import physics

from . import controls, presets
from .scene import E3, Ring, Shape, align, body_shape, ellipsoid_axes, mass_points, plane_bob, rotate, spherical_bob

FRAME_HZ = 60.0
SAMPLES_PER_FRAME = 4  # plot and trail rows per published frame
PLOT_POINTS = 1500  # plot window (ring buffer rows)
TRAIL_POINTS = 1200
HISTORY_ROWS = 20000  # trajectory rows kept for the CSV export
MAX_FRAME_DT = 0.1  # s of wall time: after a stall, do not try to catch up more than this
# wall seconds one frame may spend integrating, so a warp beyond what the machine can integrate slows
# the simulated clock instead of the frames (a stiff preset at 6000x took 0.27 s a frame without it)
TICK_BUDGET_S = 0.008
PROBE = 16.0  # after a change, the first frame integrates this much less than the last estimate allows
OVERLAY_SAMPLES = 600
OVERLAY_WINDOWS = 2.0  # a prediction covers this many plot windows ahead
DEFAULT_WARP = 1.0  # the default scene is made to be watched in real time
VIEWS = ("inertial", "body")


@dataclass
class Frame:
    """Everything one published frame shows. Vectors are in scene coordinates (inertial frame turned so
    the initial K points up, or the body frame), metres; quaternions scalar first."""

    seq: int
    t: float
    theta: float
    K: float
    E: float
    body_wxyz: np.ndarray
    world_wxyz: np.ndarray
    K_vec: np.ndarray
    omega_vec: np.ndarray
    axis_vec: np.ndarray
    torque_vec: np.ndarray | None
    mass_rest: np.ndarray | None = None
    mass_pos: np.ndarray | None = None
    bobs: list = field(default_factory=list)  # [(pivot, bob)] body frame, m
    trail: np.ndarray | None = None  # (n, 3) scene coordinates, on a sphere of radius trail_radius
    polhode: np.ndarray | None = None  # (n, 3) body frame, m: omega's tip on the drawn inertia ellipsoid
    status: str = "running"
    message: str = ""
    applied: int = 0  # sequence number of the last GUI change reflected in this frame


class Engine:
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
        self._badge: tuple | None = None  # (scenario, markdown) of the last badge
        self._badge_busy = False
        self.overlay_fidelity = "none"
        self.error = ""
        self._overlay_thread: threading.Thread | None = None
        self._overlay_gen = 0
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
        self.warp = DEFAULT_WARP if name == presets.DEFAULT else presets.suggested_warp(sc)
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
        self.sim_rate: float | None = None  # simulated s per wall s of integration, measured on the last frame
        self._probe = True  # a new run's cost is unknown
        self.achieved_warp = self.warp  # simulated s per wall s while playing, smoothed over about 10 frames
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
                self._probe = True  # a change may make integrating far dearer (a stiffer chi, a warp)
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

    def _act(self, action: str, value) -> None:
        if action == "play":
            self.playing = True
        elif action == "pause":
            self.playing = False
        elif action == "step":
            self.playing = False
            self._advance(self.warp / FRAME_HZ)
        elif action == "reset":
            self.run.reset()
            self.error = ""
            self._restarted()
        elif action == "warp":
            self.warp = self.achieved_warp = float(min(presets.WARP_MAX, max(presets.WARP_MIN, value)))
        elif action == "preset":
            sc = presets.load_preset(value)
            self.mesh = None  # a preset brings its own body
            self._load(sc, value)
            self.error = ""
        elif action == "system":
            if value != self.scenario.system:
                name = next(n for n in presets.preset_names() if presets.load_preset(n).system == value)
                self.mesh = None
                self._load(presets.load_preset(name), name)
                self.error = ""
        elif action == "fidelity":
            sc = self.scenario.replace(run=_with_fidelity(self.scenario.run, value))
            self.run.retune(sc, keep_state=False)
            self.fidelity_choice = value
            self.error = ""
            self._restarted()
        elif action == "restart_on_change":
            self.restart_on_change = bool(value)
        elif action == "view":
            self.view = value if value in VIEWS else "inertial"
            self.trail.clear()  # the trail means something else in the other frame
            self.scene_changed = True
        elif action == "exaggeration":
            self.exaggeration = float(value)
        elif action == "overlay":
            self.overlay_fidelity = value
            self.overlay_dirty = True
            self.plots_changed = True
        elif action == "tune":
            self._apply_values({"pendulum.k": "resonant"})
        elif action == "bob":
            n = len(self.scenario.plane_pendulums)
            self.bob = None if value in (None, "all") or n == 0 else min(max(int(value), 0), n - 1)
            self.values.update({k: v for k, v in controls.values_of(self.scenario, self.bob).items()
                                if k.startswith("pendulum.")})
            self.sliders_changed = True
        elif action == "polhode":
            self.show_polhode = bool(value)
            self.polhode.clear()
        elif action == "mesh":
            self._use_mesh(value)
        elif action == "upload":  # (file name, bytes) from the browser: through the parser, size-capped
            from .upload import display_name, parse_upload

            name, content = value
            sc = parse_upload(name, content)
            self.mesh = None
            self._load(sc, f"upload {display_name(name)}")
            self.error = ""
        elif action == "scenario":  # (Scenario, label) from a panel: a sweep's point, a recommended method
            sc, label = value
            self.mesh = None
            self._load(sc, label)
            self.error = ""
        else:
            raise ValueError(f"unknown action {action!r}")

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

    # ---- stepping ----------------------------------------------------------------------------
    def tick(self, wall_dt: float) -> Frame:
        """Apply pending changes, advance by warp * wall_dt (if playing) and return the frame."""
        self._apply_pending()
        if self.playing:
            t0 = self.run.t
            wall = min(max(wall_dt, 0.0), MAX_FRAME_DT)
            self._advance(self.warp * wall, floor=wall)
            if wall > 0:
                self.achieved_warp += 0.1 * ((self.run.t - t0) / wall - self.achieved_warp)
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
            cap = dt if self.sim_rate is None else self.sim_rate * TICK_BUDGET_S
            dt = min(dt, max(cap / PROBE if self._probe else cap, floor))
            self._probe = False
        t0, start = self.run.t, time.perf_counter()
        try:
            tr = self.run.advance(dt, samples=SAMPLES_PER_FRAME)
        except Exception as exc:  # a model error that is not an integrator status: report, stop
            self.run.status, self.run.message = "fault", f"{type(exc).__name__}: {exc}"
            return
        spent = time.perf_counter() - start
        self.wall_total += spent
        if self.run.t > t0 and spent > 0:
            self.sim_rate = (self.run.t - t0) / spent
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

    def _polhode_points(self, omega: np.ndarray) -> np.ndarray:
        """omega (n, 3, body components) scaled onto the drawn inertia ellipsoid w.J w = const: the
        polhode (Poinsot). The ellipsoid's semi-axes are size/sqrt(I_k) times sqrt(min I)."""
        b = self.scenario.body
        J = np.array([b.A, b.B, b.C])
        w = np.atleast_2d(omega)
        n = np.sqrt(np.maximum(np.einsum("ij,j,ij->i", w, J, w), 1e-300))[:, None]
        return w / n * (0.6 * self.shape.extent * math.sqrt(J.min()))

    def _trail_point(self, q: np.ndarray) -> np.ndarray:
        """Inertial view: the tip of the symmetry axis; body view: the direction of K in the body."""
        if self.view == "body":
            return rotate(np.array([q[0], -q[1], -q[2], -q[3]]), self.momentum_dir())
        return rotate(self.world_wxyz, rotate(q, E3))

    def momentum(self) -> np.ndarray:
        """Inertial total angular momentum now (kg m^2/s)."""
        run = self.run
        if run.model.invariants is not None and run.y.size:
            K, _ = run.model.invariants(run.y[None, :], run.p)
            return np.asarray(K[0], dtype=float)
        # closed form: K stays along the initial direction of G (physics.closed_form_state)
        _, G0, th0 = physics.initial_G(self.scenario)
        return float(run.last.K[0]) * np.array([math.sin(th0), 0.0, math.cos(th0)])

    def momentum_dir(self) -> np.ndarray:
        K = self.momentum()
        n = np.linalg.norm(K)
        return K / n if n > 0 else E3

    def _compute_overlay(self) -> None:
        """Start computing the cheaper fidelity's prediction in a background thread: a long prediction must
        not stall the frames. A newer request cancels an older one.

        Moving mass: the averaged model or the closed form from the present state (G and theta of now).
        Spherical pendulum: its averaged model from t = 0 (it needs the pendulum's initial state).
        Both pendulum systems, "closed": linear theory's envelope theta0 exp(-rate t) (MODELS B.4)."""
        if self._overlay_thread is not None and self._overlay_thread.is_alive():
            self._overlay_gen += 1  # cancel it; overlay_dirty stays set, so a later tick starts anew
            return
        self.overlay_dirty = False
        self.overlay = None
        self._overlay_gen += 1
        self.plots_changed = True
        fid = self.overlay_fidelity
        if fid == "none":
            return
        sc = self.scenario
        t0 = self.run.t
        horizon = max(OVERLAY_WINDOWS * self.plot_window(), 1.0)  # recomputed when the run passes its end
        try:
            if sc.system != "moving_mass":
                if fid == "closed":
                    d = physics.derived(sc)
                    t = np.linspace(0.0, t0 + horizon, OVERLAY_SAMPLES)
                    self.overlay = (t, d["theta0"] * np.exp(-float(d["decay_rate_linear"]) * t))
                    return
                t0, horizon = 0.0, t0 + horizon
            elif t0 > 0:  # predict from the present state: G0 and theta0 of now
                sc = sc.with_values(**{"initial.G0": float(self.run.last.K[0]),
                                       "initial.theta0": float(self.run.last.theta[0])})
            sc = sc.with_values(**{"run.t_end": horizon, "run.samples": OVERLAY_SAMPLES})
        except (physics.ScenarioError, ValueError) as exc:
            self.error = f"overlay ({fid}): {exc}"
            return
        gen = self._overlay_gen

        def progress(_fraction):
            if gen != self._overlay_gen:  # chunks between compiled calls: the place to give up
                raise _Cancelled

        def work():
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", physics.ValidityWarning)
                    tr = physics.simulate(sc, fidelity=fid, progress=progress)
            except _Cancelled:
                return
            except (physics.ScenarioError, physics.IntegrationFault, ValueError) as exc:
                if gen == self._overlay_gen:
                    self.error = f"overlay ({fid}): {exc}"
                return
            if gen == self._overlay_gen:
                self.overlay = (t0 + tr.t, tr.theta)
                self.plots_changed = True

        self._overlay_thread = threading.Thread(target=work, name="overlay", daemon=True)
        self._overlay_thread.start()

    def plot_window(self) -> float:
        """Simulated seconds the plots show at the present warp."""
        return PLOT_POINTS / (SAMPLES_PER_FRAME * FRAME_HZ) * self.warp

    def wait_overlay(self, timeout: float = 30.0) -> bool:
        """Block until the overlay being computed is done (for tests and scripts)."""
        if self._overlay_thread is not None:
            self._overlay_thread.join(timeout)
        return self.overlay is not None

    # ---- output -------------------------------------------------------------------------------
    def frame(self) -> Frame:
        run = self.run
        last = run.last
        q = last.quat[0]
        K = self.momentum()
        w_in = rotate(q, last.omega[0])
        axis = rotate(q, E3)
        torque = None
        if run.b > 0 and not run.ended:
            n = np.linalg.norm(K)
            torque = -run.b * K / n if n > 0 else None
        if self.view == "body":
            turn = np.array([q[0], -q[1], -q[2], -q[3]])  # inertial -> body components
            body_wxyz = np.array([1.0, 0, 0, 0])
            world = np.array([1.0, 0, 0, 0])
        else:
            turn = self.world_wxyz  # inertial -> the view with the initial K up
            body_wxyz = _qmul(self.world_wxyz, q)
            world = self.world_wxyz

        def to_scene(v):
            return rotate(turn, v)
        size = self.shape.extent
        self.seq += 1
        fr = Frame(seq=self.seq, t=run.t, theta=float(last.theta[0]), K=float(last.K[0]), E=float(last.E[0]),
                   body_wxyz=body_wxyz, world_wxyz=world,
                   K_vec=to_scene(K) / self.K_ref * 1.0 * size,
                   omega_vec=to_scene(w_in) / self.w_ref * 0.9 * size,
                   axis_vec=to_scene(axis) * 0.9 * size,
                   torque_vec=None if torque is None else to_scene(torque) / (np.linalg.norm(torque)) * 0.6 * size,
                   status=run.status, message=run.message, applied=self.applied_seq)
        sc = self.scenario
        if sc.mass is not None and "ux" in last.internal:
            u = np.array([last.internal[k][0] for k in ("ux", "uy", "uz")])
            fr.mass_rest, fr.mass_pos = mass_points(sc.mass.rho, u, self.exaggeration)
        elif sc.mass is not None:
            fr.mass_rest, fr.mass_pos = mass_points(sc.mass.rho, np.zeros(3), 1.0)
        if sc.pendulum is not None:
            a = last.internal.get("alpha", [0.0])[0]
            b = last.internal.get("beta", [0.0])[0]
            fr.bobs = [spherical_bob(sc.pendulum.h, sc.pendulum.l, a, b)]
        for i, pp in enumerate(sc.plane_pendulums):
            a = last.internal.get(f"a{i + 1}", [0.0])[0]
            fr.bobs.append(plane_bob(*pp.geometry(), pp.l, a))
        fr.trail = self.trail.values() * 0.9 * size  # the e3 arrow's tip draws it
        if self.show_polhode:
            fr.polhode = self.polhode.values()
        return fr

    def ellipsoid(self) -> np.ndarray:
        b = self.scenario.body
        return ellipsoid_axes(b.A, b.B, b.C, 0.6 * self.shape.extent)

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

    @property
    def has_overlay(self) -> bool:
        return self.overlay is not None

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

    def badge(self, block: bool = False) -> str:
        """Auto's choice (model, method, error bound against the requested accuracy, and why) and the
        averaged model's validity conditions, as markdown. Computed once per scenario, in a background
        thread (up to 0.4 s for three plane pendulums: the frames go on meanwhile); until it is ready,
        a placeholder. ``block``: wait for it instead."""
        sc = self.scenario
        done = self._badge
        if done is not None and done[0] is sc:
            return done[1]
        if block:
            self._badge = (sc, _badge_text(sc))
            return self._badge[1]
        with self._lock:
            start = not self._badge_busy
            self._badge_busy = True
        if start:
            threading.Thread(target=self._badge_worker, args=(sc,), name="badge", daemon=True).start()
        return "_auto: working out its choice..._"

    def _badge_worker(self, sc: physics.Scenario) -> None:
        try:
            self._badge = (sc, _badge_text(sc))
        finally:
            self._badge_busy = False  # the next call starts another if the scenario has changed since

    def csv(self) -> bytes:
        buf = io.StringIO()
        np.savetxt(buf, self.history.values(), delimiter=",", header=",".join(self.history_columns), comments="",
                   fmt="%.17g")
        return buf.getvalue().encode()

    def toml(self) -> bytes:
        return self.scenario.to_toml().encode()


class _Cancelled(Exception):
    """A newer overlay request replaced this one."""


def _badge_text(sc: physics.Scenario) -> str:
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            d = physics.derived(sc)
            conds = physics.validity_conditions(sc)
    except Exception as exc:  # never let the badge break a frame
        return f"auto: unavailable ({exc})"
    head = f"**auto → {d['auto_fidelity']}** · {d.get('auto_method', '')}"
    if conds:
        head += f"  \naveraged model's conditions {'hold' if all(c.holds for c in conds) else 'fail'}:"
    lines = [f"{'OK' if c.holds else 'FAILS'}: {c}" for c in conds]
    bound = d.get("auto_error_bound")
    shown_bound = isinstance(bound, float) and bound > 0
    lines.append(f"requested accuracy: {d.get('auto_accuracy', 'not set')}"
                 + (f"; error bound of the choice {bound:.2g} rad" if shown_bound else ""))
    return head + "  \n" + "  \n".join(lines) + f"  \n_{d['auto_reason']}_"


def _with_fidelity(run: physics.Run, fidelity: str) -> physics.Run:
    import dataclasses

    return dataclasses.replace(run, fidelity=fidelity)


def _qmul(a, b):
    from .scene import qmul

    return qmul(a, b)
