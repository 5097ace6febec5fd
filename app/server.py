"""The viser server: one Session (its own simulation, controls and scene) per browser tab.

A session's loop thread owns the Engine: it applies what the GUI callbacks recorded, integrates
as finely as the integrator needs (LiveRun.advance) and publishes about 60 frames per second inside
``client.atomic()``. Callbacks only record values. Nothing a user does can end the loop or the server.
"""

from __future__ import annotations

import gc
import threading
import time
import traceback
import warnings
from collections import deque

import numpy as np
import viser

import physics

from . import controls, plots, presets
from .mesh import INERTIA_SHAPE, asset_names
from .scene import box_mesh, cylinder_mesh, trail_segments
from .state import FRAME_HZ, Engine

COLORS = {"body": (120, 150, 200), "ellipsoid": (240, 200, 80), "mass": (220, 40, 40), "rest": (60, 60, 60),
          "spring": (40, 40, 40), "K": (30, 160, 60), "omega": (40, 90, 230), "axis": (120, 120, 120),
          "torque": (220, 60, 200), "trail": (230, 120, 20), "polhode": (150, 40, 200), "bob": (200, 30, 30),
          "cavity": (60, 160, 230)}


SCENE_SIZE = 1.5  # scene units the body spans, whatever its size in metres
CROWD = 4  # tabs on one server beyond which each gets CROWD_HZ frames per second instead of FRAME_HZ
CROWD_HZ = 40.0  # still smooth, and ten tabs fit one core's worth of Python (docs/reliability.md)
CROWD_PLOT_HZ = 5.0  # plots, readouts and trails of a crowd: their arrays are the heavy part of a frame


class Session:
    """One browser tab."""

    def __init__(self, server: viser.ViserServer, client: viser.ClientHandle, scenario: physics.Scenario | None,
                 stats: dict, mesh=None):
        self.server = server
        self.client = client
        self.stats = stats
        note = client.gui.add_markdown("**Quasirigid explorer** · preparing the integrator (the first run on a "
                                       "machine compiles it, about half a minute)...")
        try:
            self.engine = Engine(scenario, mesh=mesh)
        finally:
            note.remove()
        self.stop = threading.Event()
        self.published = 0
        self.first_frame_after: dict[int, float] = {}  # change seq -> latency (s) of its first frame
        self.frame_ms: deque = deque(maxlen=600)  # (tick, publish) wall ms of recent frames
        self._build_gui()
        self._build_scene()
        self.thread = threading.Thread(target=self._loop, name=f"session-{client.client_id}", daemon=True)
        self.thread.start()

    # ---- GUI -------------------------------------------------------------------------------------
    def _build_gui(self) -> None:
        gui, eng = self.client.gui, self.engine
        gui.configure_theme(control_width="large")
        self.status_md = gui.add_markdown("**Quasirigid explorer**")
        self.readout_md = gui.add_markdown("")
        self.error_md = gui.add_markdown("")
        with gui.add_folder("Plots"):
            self.plots = plots.build_plots(gui, eng.plot_data())
        with gui.add_folder("Playback"):
            self.play_btn = gui.add_button("Play", icon=None)
            self.pause_btn = gui.add_button("Pause")
            self.step_btn = gui.add_button("Step")
            self.reset_btn = gui.add_button("Reset")
            self.warp = gui.add_slider("time warp (log10 x)", min=-1.0, max=4.0, step=0.05,
                                       initial_value=float(np.log10(eng.warp)),
                                       hint="simulated seconds per wall second, as a power of ten (0 = 1x, 3 = 1000x)")
            self.restart = gui.add_checkbox("restart on change", False,
                                            hint="restart from t = 0 on every change instead of keeping the state")
        with gui.add_folder("Model"):
            self.preset = gui.add_dropdown("Preset", presets.preset_names(), initial_value=eng.preset
                                           if eng.preset in presets.preset_names() else presets.DEFAULT)
            self.system = gui.add_dropdown("System", list(controls.SYSTEM_LABELS),
                                           initial_value=_system_label(eng.scenario.system))
            self.fidelity = gui.add_dropdown("Fidelity", list(controls.FIDELITIES), initial_value=eng.fidelity_choice,
                                             hint="full multibody, averaged (quasi-rigid), closed form, or auto")
            self.badge_md = gui.add_markdown("")
            self.overlay = gui.add_dropdown("Overlay prediction", ["none", "averaged", "closed"],
                                            initial_value="none",
                                            hint="a cheaper fidelity's theta(t), computed with physics.simulate")
            self.tune_btn = gui.add_button("Tune to resonance", hint="spherical pendulum: k = resonant (MODELS B.5)")
        self.panels: dict = {}
        self.sliders, self.folders = controls.build_sliders(gui, eng.values)
        with self.folders["Pendulum damper"]:
            self.bob = gui.add_dropdown("bob", ["all", "1", "2", "3"], initial_value="all",
                                        hint="plane pendulums: which bob the sliders above edit")
        with gui.add_folder("View"):
            self.view = gui.add_dropdown("Frame", ["inertial", "body"], initial_value="inertial",
                                         hint="inertial: K fixed and pointing up; body: the body stays still")
            self.exag = gui.add_slider("exaggerate u (x)", min=1.0, max=1000.0, step=1.0, initial_value=10.0,
                                       hint="the mass's displacement is drawn this many times larger")
            self.polhode = gui.add_checkbox("polhode", False, hint="the tip of omega on the inertia ellipsoid, in "
                                            "the body (Poinsot): closed loops when nothing dissipates")
            self.body_mesh = gui.add_dropdown("body drawn as", [INERTIA_SHAPE, *asset_names()],
                                              initial_value=INERTIA_SHAPE,
                                              hint="a mesh from assets/meshes: its inertia ratios replace A, B, C "
                                              "(scaled to keep A + B + C); restarts the run")
        with gui.add_folder("File", expand_by_default=False):
            self.toml_btn = gui.add_button("Download scenario (TOML)")
            self.csv_btn = gui.add_button("Download trajectory (CSV)")
            self.upload = gui.add_upload_button("Load scenario (TOML)", mime_type=".toml",
                                                hint="a scenario file, as `python -m physics` reads (64 kB at most)")
        self._lazy_panel("Speed vs accuracy", "speed_panel", "SpeedPanel",
                         lambda sc: eng.request("scenario", (sc, f"{eng.preset} (recommended method)")))
        self._lazy_panel("Sweep", "sweep_panel", "SweepPanel",
                         lambda sc: eng.request("scenario", (sc, "sweep point")), scene=self.client.scene)

        def on(handle, action, convert=lambda v: v):
            @handle.on_update
            def _(event):
                if event.client is None:  # our own assignment of a value: not a user's change
                    return
                eng.request(action, convert(handle.value))

        def click(handle, action):
            @handle.on_click
            def _(_event):
                eng.request(action)

        click(self.play_btn, "play")
        click(self.pause_btn, "pause")
        click(self.step_btn, "step")
        click(self.reset_btn, "reset")
        click(self.tune_btn, "tune")
        on(self.warp, "warp", lambda v: 10.0 ** float(v))
        on(self.restart, "restart_on_change")
        on(self.preset, "preset")
        on(self.system, "system", lambda v: controls.SYSTEM_LABELS[v])
        on(self.fidelity, "fidelity")
        on(self.overlay, "overlay")
        on(self.view, "view")
        on(self.exag, "exaggeration")
        on(self.polhode, "polhode")
        on(self.body_mesh, "mesh")
        on(self.bob, "bob", lambda v: None if v == "all" else int(v) - 1)
        for key, slider in self.sliders.items():
            self._bind_slider(key, slider)

        @self.toml_btn.on_click
        def _(event):
            (event.client or self.client).send_file_download("scenario.toml", eng.toml(), save_immediately=True)

        @self.csv_btn.on_click
        def _(event):
            (event.client or self.client).send_file_download("trajectory.csv", eng.csv(), save_immediately=True)

        @self.upload.on_upload
        def _(_event):
            f = self.upload.value
            eng.request("upload", (f.name, f.content))

    def _lazy_panel(self, title: str, module: str, cls: str, apply, **options) -> None:
        """A folder whose panel is built on first open: panels pull in plotly (and its script in the
        browser), which the first frame should not wait for."""
        gui = self.client.gui
        with gui.add_folder(title, expand_by_default=False) as folder:
            opener = gui.add_button(f"Open the {title.lower()} panel")

        @opener.on_click
        def _(_event):
            import importlib

            try:
                panel_class = getattr(importlib.import_module(f".{module}", __package__), cls)
                with folder:
                    self.panels[title] = panel_class(gui, lambda: self.engine.scenario, apply, **options)
                opener.remove()
            except Exception as exc:  # a panel that cannot open says so; the tab runs on
                self.engine.error = f"{title} panel: {type(exc).__name__}: {exc}"

    def _bind_slider(self, key: str, slider) -> None:
        @slider.on_update
        def _(event):
            if event.client is None:
                return
            self.engine.request_value(key, float(slider.value))

    def _sync_widgets(self) -> None:
        """After a preset or system change: slider values, ranges and which folders apply."""
        eng = self.engine
        system = eng.scenario.system
        for key, slider in self.sliders.items():  # assign only what differs: each assignment is a message
            p = controls.BY_KEY[key]
            lo, hi = controls.slider_range(p, eng.values[key])
            _set(slider, "min", lo)
            _set(slider, "max", hi)
            _set(slider, "value", min(max(eng.values[key], lo), hi))
            _set(slider, "disabled", system not in p.systems)
        _set(self.folders["Pendulum damper"], "visible", system != "moving_mass")
        for title in ("Seed 004: mass, medium, braking", "Friction and cavity"):
            _set(self.folders[title], "visible", system == "moving_mass")
        _set(self.tune_btn, "visible", system == "spherical_pendulum")
        n = len(eng.scenario.plane_pendulums)
        _set(self.bob, "visible", n > 0)
        if n > 0:
            _set(self.bob, "options", ("all", *(str(i + 1) for i in range(n))))
            _set(self.bob, "value", "all" if eng.bob is None else str(eng.bob + 1))
        _set(self.body_mesh, "value", eng.mesh.name if eng.mesh is not None and eng.mesh.name in asset_names()
             else INERTIA_SHAPE)
        for panel in self.panels.values():  # a new scene may have other sliders to sweep
            if hasattr(panel, "refresh"):
                panel.refresh()
        _set(self.warp, "value", float(np.log10(eng.warp)))
        if eng.preset in presets.preset_names():
            _set(self.preset, "value", eng.preset)
        _set(self.system, "value", _system_label(system))
        _set(self.fidelity, "value", eng.fidelity_choice)

    # ---- scene -----------------------------------------------------------------------------------
    def _build_scene(self) -> None:
        sc = self.client.scene
        self.client.camera.position = (3.0, -3.4, 1.9)
        self.client.camera.look_at = (0.0, 0.0, 0.3)
        self.root = f"/s{self.client.client_id}"
        # viser's default environment map costs a browser without a GPU (software WebGL) a 4-6 s stall
        # in about half the page loads, which pushed the first drawn frame past 5 s
        # (bench/explorer_startup.py); a hemisphere light gives the same soft fill at no such cost.
        sc.configure_environment_map(None)
        sc.add_light_hemisphere(f"{self.root}_fill", sky_color=(255, 255, 255), ground_color=(120, 120, 130),
                                intensity=1.5)
        sc.add_grid(f"{self.root}_grid", width=6.0, height=6.0, cell_size=0.25, position=(0.0, 0.0, -1.4))
        self.world = sc.add_frame(self.root, show_axes=False)
        self.handles: dict = {}
        self._draw_static()

    def _draw_static(self) -> None:
        """The parts that change only with the parameters: body shape, ellipsoid, parts' anchors."""
        eng, sc, r = self.engine, self.client.scene, self.root
        old = [h for v in self.handles.values() for h in (v if isinstance(v, list) else [v])]
        for h in reversed(old):  # children before their parent frame
            if "/body/" in h.name and "body" in self.handles and h is not self.handles["body"]:
                continue  # removed with /body
            try:
                h.remove()
            except Exception:
                pass
        self.handles = {}
        shape = eng.shape
        k = self.k = SCENE_SIZE / shape.extent  # scene units per metre: every body looks the same size
        s = SCENE_SIZE
        body = sc.add_frame(f"{r}/body", show_axes=True, axes_length=0.6 * s, axes_radius=0.01 * s)
        self.handles["body"] = body
        if eng.mesh is not None:
            vertices, faces = eng.mesh.vertices, eng.mesh.faces
        elif shape.kind == "box":
            vertices, faces = box_mesh(shape.dims)
        else:
            vertices, faces = cylinder_mesh(shape.radius, shape.height)
        self.handles["shape"] = sc.add_mesh_simple(f"{r}/body/shape", np.asarray(vertices) * k, faces,
                                                   color=COLORS["body"], opacity=0.45, flat_shading=False)
        self.handles["ellipsoid"] = sc.add_icosphere(f"{r}/body/ellipsoid", radius=1.0, color=COLORS["ellipsoid"],
                                                     scale=tuple(eng.ellipsoid() * k), opacity=0.15, subdivisions=3)
        scn = eng.scenario
        if scn.cavity is not None:
            self.handles["cavity"] = sc.add_icosphere(f"{r}/body/cavity", radius=max(scn.cavity.a0 * k, 0.03 * s),
                                                      color=COLORS["cavity"], opacity=0.35)
        if scn.mass is not None:
            self.handles["rest"] = sc.add_icosphere(f"{r}/body/rest", radius=0.025 * s, color=COLORS["rest"],
                                                    position=(0.0, 0.0, scn.mass.rho * k))
            self.handles["mass"] = sc.add_icosphere(f"{r}/body/mass", radius=0.05 * s, color=COLORS["mass"])
            self.handles["spring"] = sc.add_line_segments(f"{r}/body/spring", np.zeros((1, 2, 3)), COLORS["spring"],
                                                          thickness=0.008 * s)
            self.handles["exag"] = sc.add_label(f"{r}/body/exag_label", "u x 10",
                                                position=(0.0, 0.0, scn.mass.rho * k + 0.1 * s))
        for i, _ in enumerate(eng.frame().bobs):
            self.handles[f"arm{i}"] = sc.add_line_segments(f"{r}/body/arm{i}", np.zeros((1, 2, 3)), (30, 30, 30),
                                                           thickness=0.012 * s)
            self.handles[f"bob{i}"] = sc.add_icosphere(f"{r}/body/bob{i}", radius=0.04 * s, color=COLORS["bob"])
        arrows = np.zeros((4, 2, 3))
        colors = np.array([COLORS["K"], COLORS["omega"], COLORS["axis"], COLORS["torque"]], dtype=np.uint8)
        self.handles["arrows"] = sc.add_arrows(f"{r}/arrows", arrows, colors, shaft_radius=0.012 * s,
                                               head_radius=0.035 * s, head_length=0.08 * s)
        self.handles["labels"] = [sc.add_label(f"{r}/lab_{n}", n, font_screen_scale=0.8)
                                  for n in ("K", "omega", "e3", "torque")]
        self.handles["trail"] = sc.add_line_segments(f"{r}/trail", np.zeros((1, 2, 3)), COLORS["trail"],
                                                     thickness=0.003 * s)
        self.handles["polhode"] = sc.add_line_segments(f"{r}/body/polhode", np.zeros((1, 2, 3)), COLORS["polhode"],
                                                       thickness=0.004 * s, visible=False)

    def _publish(self, fr, plots_now: bool) -> None:
        eng = self.engine
        with self.client.atomic():
            if eng.scene_changed:
                eng.scene_changed = False
                self._draw_static()
                eng.mark_drawn()
            h = self.handles
            h["body"].wxyz = fr.body_wxyz
            origin = np.zeros(3)
            k = self.k
            vecs = [k * v for v in (fr.K_vec, fr.omega_vec, fr.axis_vec)]
            vecs.append(k * fr.torque_vec if fr.torque_vec is not None else origin)
            h["arrows"].points = np.array([[origin, v] for v in vecs])
            if plots_now:  # labels and trails change slowly: at the plots' rate, not every frame
                for lab, v in zip(h["labels"], vecs, strict=True):
                    lab.position = tuple(1.08 * v)
                    _set(lab, "visible", bool(np.linalg.norm(v) > 0))
            if fr.mass_pos is not None and "mass" in h:
                h["mass"].position = tuple(k * fr.mass_pos)
                h["spring"].points = k * np.array([[fr.mass_rest, fr.mass_pos]])
                h["exag"].text = f"u x {eng.exaggeration:g}"
            for i, (pivot, bob) in enumerate(fr.bobs):
                if f"bob{i}" in h:
                    h[f"bob{i}"].position = tuple(k * bob)
                    h[f"arm{i}"].points = k * np.array([[pivot, bob]])
            if plots_now and fr.trail is not None and len(fr.trail):
                h["trail"].points = trail_segments(k * fr.trail)
            _set(h["polhode"], "visible", fr.polhode is not None)
            if plots_now and fr.polhode is not None and len(fr.polhode):
                h["polhode"].points = trail_segments(k * fr.polhode)
            if eng.sliders_changed:
                eng.sliders_changed = False
                self._sync_widgets()
            if plots_now and eng.plots_changed:
                eng.plots_changed = False
                plots.update_plots(self.plots, eng.plot_data(), eng.has_overlay)
                self.readout_md.content = _readout_md(eng)
            _set(self.badge_md, "content", eng.badge())  # cached: computed once per scenario, off this thread
            _set(self.error_md, "content", f"<span style='color:#c00'>**Rejected:** {eng.error}</span>"
                 if eng.error else "")
            state = "playing" if eng.playing else "paused"
            if fr.status != "running":
                state = fr.status + (": " + fr.message if fr.message else "")
            warp = f"warp {eng.warp:.3g}x"
            if eng.playing and fr.status == "running" and eng.achieved_warp < 0.8 * eng.warp:
                warp += f" (reaching {eng.achieved_warp:.3g}x: as fast as this machine integrates)"
            _set(self.status_md, "content", f"**Quasirigid explorer** · {state} · {warp}")

    # ---- the loop ----------------------------------------------------------------------------------
    def _loop(self) -> None:
        last = deadline = time.perf_counter()
        next_plot = 0.0
        while not self.stop.is_set():
            now = time.perf_counter()
            dt, last = now - last, now
            try:
                fr = self.engine.tick(dt)
                ticked = time.perf_counter()
                plots_now = now >= next_plot
                if plots_now:
                    crowded = self.stats.get("sessions", 1) > CROWD
                    next_plot = now + 1.0 / (CROWD_PLOT_HZ if crowded else plots.PLOT_HZ)
                self._publish(fr, plots_now)
                self.frame_ms.append((1e3 * (ticked - now), 1e3 * (time.perf_counter() - ticked)))
                self.published += 1
                self.stats["frames"] = self.stats.get("frames", 0) + 1
                done = time.perf_counter()
                for seq, t0 in list(self.engine.change_times.items()):
                    if seq <= fr.applied and seq not in self.first_frame_after:
                        self.first_frame_after[seq] = done - t0
                        del self.engine.change_times[seq]
            except Exception:  # never let one bad frame end the tab's simulation
                if self.stop.is_set():
                    break
                self.engine.error = "internal error: " + traceback.format_exc(limit=1).strip().splitlines()[-1]
                traceback.print_exc()
                time.sleep(0.2)
            # a fixed schedule, so the rate does not drift; many tabs share the GIL, so a crowd gets fewer frames
            deadline += 1.0 / (FRAME_HZ if self.stats.get("sessions", 1) <= CROWD else CROWD_HZ)
            sleep = deadline - time.perf_counter()
            if sleep > 0:
                self.stop.wait(sleep)
            else:
                deadline = time.perf_counter()  # behind (a slow frame): do not try to catch up

    def close(self) -> None:
        self.stop.set()


def _set(handle, name: str, value) -> None:
    if getattr(handle, name) != value:
        setattr(handle, name, value)


def _system_label(system: str) -> str:
    return next(k for k, v in controls.SYSTEM_LABELS.items() if v == system)


def _readout_md(eng: Engine) -> str:
    """One ``name = value`` line per readout (the browser test reads them back)."""
    d = eng.readouts()
    return "  \n".join(f"{k} = {v}" for k, v in d.items()) + f"  \npreset: {eng.preset}"


class App:
    """The server and its sessions."""

    def __init__(self, host: str = "127.0.0.1", port: int = 8080, scenario: physics.Scenario | None = None,
                 mesh=None, server: viser.ViserServer | None = None):
        """``server``: one already serving (``python -m app`` starts it before loading the physics, so a
        browser fetches the page meanwhile); tabs that connected before are served now."""
        self.scenario = scenario
        self.mesh = mesh
        # a tab's last frame can race its disconnection; viser then warns that the message is dropped
        warnings.filterwarnings("ignore", message="Queued a .* on a closed connection")
        self.server = server or viser.ViserServer(host=host, port=port, label="Quasirigid")
        self.sessions: dict[int, Session] = {}
        self.stats: dict = {}
        self.server.on_client_connect(self._connect)
        self.server.on_client_disconnect(self._disconnect)

    def _connect(self, client: viser.ClientHandle) -> None:
        try:
            self.sessions[client.client_id] = Session(self.server, client, self.scenario, self.stats, self.mesh)
            self.stats["sessions"] = len(self.sessions)
        except Exception:
            traceback.print_exc()

    def _disconnect(self, client: viser.ClientHandle) -> None:
        s = self.sessions.pop(client.client_id, None)
        self.stats["sessions"] = len(self.sessions)
        if s is not None:
            s.close()
            # A closed session is cyclic garbage (the client's GUI handles hold our callbacks, which close
            # over the session), which only a full collection frees; CPython runs one only after the
            # long-lived objects grow by a quarter (~35k here), so each reconnection kept its ~3 MB for
            # dozens of reconnections. viser holds the client handle until this callback returns: collect
            # from another thread, once the session's loop has ended and viser has let go.
            threading.Thread(target=_collect_closed, args=(s.thread,), name="collect-session", daemon=True).start()

    @property
    def port(self) -> int:
        return self.server.get_port()

    def close(self) -> None:
        for s in list(self.sessions.values()):
            s.close()
        self.server.stop()


def _collect_closed(loop: threading.Thread, delay: float = 1.0) -> None:
    """Free a closed session (see App._disconnect) and hand its memory back to the system."""
    loop.join(timeout=5.0)  # its frame holds the session until the loop ends
    time.sleep(delay)  # viser's disconnect handling drops its last reference to the client handle
    gc.collect()  # a full collection: the session's objects have long reached the oldest generation
    _trim_heap()


def _trim_heap() -> None:
    """Hand freed memory back to the system after a tab's session is freed: glibc keeps its buffers
    otherwise (docs/reliability.md). Elsewhere than glibc this does nothing."""
    try:
        import ctypes

        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        pass


def warm_up() -> None:
    """Load (or compile) the integrator and the kernels once, so the first tab is quick."""
    run = physics.LiveRun(physics.default_scenario())
    run.advance(0.01)
