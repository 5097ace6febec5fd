"""A replay anyone can open: the explorer's 3-D scene recorded into one self-contained HTML file.

The same Engine and Drawing as a browser tab are driven at a fixed frame rate over the played seconds, on a
recording viser server that no browser connects to; viser's scene serializer (``get_scene_serializer``,
``insert_sleep``, ``as_html``) keeps every scene message with its time, and its client (inlined in the page)
plays them back with play, pause and a scrub bar. GUI messages are never serialized, so the page also carries
the plots, the legend and the scenario (``app.replay.page``).
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import physics

from ..engine.clock import PLOT_HZ
from ..engine.engine import Engine

REPLAY_FPS = 30.0  # frames per played second: smooth to the eye, half the live rate, half the file
MIN_SECONDS = 1.0 / REPLAY_FPS  # one frame: 5e-324 s wrote a replay of 0 frames
MAX_SECONDS = 600.0  # played seconds a replay may last: ten minutes (default scene: 4.9 MB, ~1 min of work)
MAX_BYTES = 150 * 2**20  # an HTML file larger than this is refused rather than written (a browser chokes on it)
_record_lock = threading.Lock()  # viser's serializer registry is per server, but one recording at a time is plenty


@dataclass
class Replay:
    """A finished recording: the page, and what it shows."""

    html: str
    seconds: float  # played
    simulated: float  # simulated seconds, t at the last frame
    frames: int
    warp: float
    title: str

    @property
    def size(self) -> int:
        return len(self.html.encode())


class _RecordingHost:
    """What ``app.scene.drawing.Drawing`` uses of a browser tab (scene, gui, camera, id), served by a recording server:
    its scene is the server's, the one the serializer records; the camera it sets is the replay's initial view."""

    def __init__(self, server):
        self.scene = server.scene
        self.gui = server.gui  # the legend goes here; GUI messages are not recorded (app.replay.page shows it)
        self.camera = server.initial_camera
        self.client_id = 0


def check_seconds(seconds) -> float:
    """Played seconds as a float in [MIN_SECONDS, MAX_SECONDS]; ValueError naming the parameter otherwise."""
    allowed = f"allowed: 1/{REPLAY_FPS:g} s (one frame) to {MAX_SECONDS:g} s, played"
    try:
        s = float(seconds)
    except (TypeError, ValueError):
        raise ValueError(f"--seconds {seconds!r} is not a number; {allowed}") from None
    if not MIN_SECONDS <= s <= MAX_SECONDS:  # also nan
        raise ValueError(f"--seconds {seconds!r} is out of range; {allowed}")
    return s


def record(scenario: physics.Scenario | None, seconds: float, *, title: str, toml_text: str | None = None,
           warp: float | None = None, engine: Engine | None = None, fps: float = REPLAY_FPS,
           progress=None, changes: list | None = None) -> Replay:
    """Play ``scenario`` (the default scene if None) for ``seconds`` at ``fps`` frames per played second and
    return the replay page. ``warp``: simulated seconds per played second (default: the one the explorer
    chooses for the scene). ``engine``: a prepared one instead (the export button's copy of a tab's view);
    ``progress(fraction)`` is called now and then. ``changes``: (t, scenario) pairs a tab's run went on through,
    made again when the replay's run reaches each t (within one frame's simulated time). Raises ValueError for a
    bad ``seconds`` and physics.ScenarioError for a scenario that does not run."""
    import viser

    from ..scene.drawing import Drawing
    from .page import page

    seconds = check_seconds(seconds)
    changes = sorted(changes or [], key=lambda c: c[0])
    eng = engine if engine is not None else Engine(scenario)
    if warp is not None:
        eng.warp = float(warp)
    eng.playing = True
    frames = int(round(seconds * fps))
    dt = 1.0 / fps
    plot_every = max(1, int(round(fps / PLOT_HZ)))  # labels and the trail at the live plots' rate
    with _record_lock:
        server = viser.ViserServer(host="127.0.0.1", port=0, label="Quasirigid replay", verbose=False)
        try:
            drawing = Drawing(_RecordingHost(server), eng)
            drawing.update(eng.frame(), True)  # the scene as a tab first shows it, before the recording starts
            serializer = server.get_scene_serializer()  # from here, every scene message is kept with its time
            pending = list(changes)
            for i in range(1, frames + 1):
                while pending and pending[0][0] <= eng.run.t:  # the tab's changes, at the frame that reaches them
                    eng.replay_retune(pending.pop(0)[1])
                # exactly warp * dt simulated per frame: the live clock's wall-time budget (app.engine.clock) would make
                # a replay depend on how busy this machine was while recording it
                eng._advance(eng.warp * dt)
                drawing.update(eng.frame(), i % plot_every == 0)
                serializer.insert_sleep(dt)
                if progress is not None and i % 30 == 0:
                    progress(i / frames)
            legend = drawing.legend.markdown.content
            html = page(serializer.as_html(), title=title, toml_text=toml_text or eng.scenario.to_toml(),
                        trajectory=_trajectory(eng), legend=legend,
                        caption=f"{seconds:g} s played at {eng.warp:.3g}x: t = 0 to {eng.run.t:.4g} s simulated, "
                        f"model: {eng.readouts().get('fidelity', eng.scenario.run.fidelity)}")
        finally:
            server.stop()
    replay = Replay(html=html, seconds=seconds, simulated=float(eng.run.t), frames=frames, warp=float(eng.warp),
                    title=title)
    if replay.size > MAX_BYTES:
        raise ValueError(f"--seconds {seconds:g} makes a replay of {replay.size / 2**20:.0f} MB; allowed: at most "
                         f"{MAX_BYTES / 2**20:.0f} MB (record fewer seconds)")
    return replay


def _trajectory(eng: Engine) -> physics.Trajectory:
    """The run from t = 0 as a physics.Trajectory, from the rows the engine keeps for the CSV export."""
    rows, _ = eng.history.snapshot()
    cols = list(eng.history_columns)
    col = {name: rows[:, i] for i, name in enumerate(cols)}
    base = ("t", "theta", "K", "E", "wx", "wy", "wz", "qw", "qx", "qy", "qz")
    return physics.Trajectory(t=col["t"], theta=col["theta"], K=col["K"], E=col["E"],
                              omega=rows[:, [cols.index(c) for c in base[4:7]]],
                              quat=rows[:, [cols.index(c) for c in base[7:]]],
                              internal={c: col[c] for c in cols if c not in base}, info={})


def copy_of_tab(eng: Engine) -> Engine:
    """A fresh engine on the scene a tab's run started from, with its view, exaggeration and warp, from t = 0:
    what the export button records (with ``eng.retunes``, the changes made since), without touching the tab's
    own run. A tab that made more changes than it keeps (RETUNES_KEPT) is recorded on its present scene."""
    copy = Engine(eng.start_scenario if eng.retunes is not None else eng.scenario, mesh=eng.mesh)
    copy.view = eng.view
    copy.view_values = dict(eng.view_values)
    copy.show_polhode = eng.show_polhode
    copy.warp = eng.warp
    return copy
