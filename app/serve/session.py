"""One browser tab: its engine, panel and scene, and the loop thread that owns the engine. The loop applies
what the GUI callbacks recorded, integrates as finely as the integrator needs (LiveRun.advance) and
publishes about 60 frames per second inside ``client.atomic()``. Nothing a user does can end the loop.
"""

from __future__ import annotations

import threading
import time
import traceback
import weakref
from collections import deque

import viser

import physics

from ..engine.clock import PLOT_HZ
from ..engine.engine import Engine
from ..engine.frame import non_finite
from ..panel.panel import Panel
from ..scene.drawing import Drawing
from .backlog import Backlog
from .message_guard import screen_gui_updates
from .pace import Pace
from .upload_cap import cap_streamed_uploads

CROWD_PLOT_HZ = 5.0  # plots, readouts and trails of a crowd: their arrays are the heavy part of a frame


class Session:
    """One browser tab."""

    def __init__(self, server: viser.ViserServer, client: viser.ClientHandle, scenario: physics.Scenario | None,
                 stats: dict, mesh=None, engine: Engine | None = None, klass=None):
        self.server = server
        self.client = client
        self.stats = stats
        # brief: on a machine without the compiled kernels the scene starts on their interpreted twins at once
        note = client.gui.add_markdown("**Quasirigid explorer** · preparing the scene...")
        try:  # ``engine``: one made already (class mode's "Explore from here", app.serve.classroom)
            self.engine = engine if engine is not None else Engine(scenario, mesh=mesh)
        finally:
            note.remove()
        self.stop = threading.Event()
        self.published = 0
        self.last_good = None  # the last frame published whose numbers were all finite (_publish)
        self.first_frame_after: dict[int, float] = {}  # change seq -> latency (s) of its first frame
        self.frame_ms: deque = deque(maxlen=600)  # (tick, publish) wall ms of recent frames
        self.pace = Pace()  # how often to publish, from what a frame costs and how many tabs there are
        self.backlog = Backlog(client)  # whether viser still holds the last frame unsent (app.serve.backlog)
        # a server started on a scenario or mesh of its own shows that, not the browser's last scene
        self.panel = Panel(client, self.engine, restore=scenario is None and mesh is None and engine is None,
                           still=engine is None, klass=klass)  # klass: a class's challenge (app.serve.scoreboard)
        # Both stay on the tab's connection for as long as the tab (a class student's "Follow the class" ends
        # this session and leaves the screens on): they tell this session through weak references, or each
        # explore and follow would keep the session it left in memory until the tab closed.
        cap_streamed_uploads(client.gui, _weakly(self._refuse_upload))  # the size cap holds while the parts arrive
        screen_gui_updates(client.gui, _weakly(self._refuse_value))  # a value that does not fit never reaches viser
        self.drawing = Drawing(client, self.engine)
        self.thread = threading.Thread(target=self._loop, name=f"session-{client.client_id}", daemon=True)
        self.thread.start()

    def _refuse_upload(self, message: str) -> None:
        self.engine.upload_note = ("refused", f"Not loaded: {message}. The scene is unchanged.")  # beside the button

    def _refuse_value(self, message: str) -> None:
        self.engine.error = message  # the panel's note, as the app's own refusals are shown

    def _publish(self, fr, plots_now: bool) -> None:
        """Send the frame to the tab; one with a NaN or infinity in it is never sent (the browser would draw
        nothing or garbage): the last good frame is shown again, with a note naming what was not finite."""
        bad = non_finite(fr)
        if bad is not None:
            self.engine.error = (f"the frame at t = {fr.t:.6g} s has a non-finite {bad}; "
                                 "the last drawing that was finite is kept")
            if self.last_good is None:
                return
            fr, plots_now = self.last_good, False
        else:
            self.last_good = fr
        with self.client.atomic():
            self.drawing.update(fr, plots_now)
            self.panel.update(fr, plots_now)

    def _loop(self) -> None:
        last = deadline = time.perf_counter()
        next_plot = 0.0
        while not self.stop.is_set():
            now = time.perf_counter()
            dt, last = now - last, now
            cpu = time.thread_time()
            tabs = self.stats.get("sessions", 1)
            try:
                fr = self.engine.tick(dt)
                ticked = time.perf_counter()
                plots_now = now >= next_plot
                # while viser still holds the last frame unsent, a new one would only replace it; but the first
                # frame after a change goes out at once, so a change is never left unshown behind a slow sender
                changed = any(seq <= fr.applied for seq in list(self.engine.change_times))
                if changed or not self.backlog.behind():
                    if plots_now:
                        next_plot = now + 1.0 / (CROWD_PLOT_HZ if self.pace.crowded(tabs) else PLOT_HZ)
                    self._publish(fr, plots_now)
                    self.backlog.published()
                    self.frame_ms.append((1e3 * (ticked - now), 1e3 * (time.perf_counter() - ticked)))
                    self.published += 1
                    self.pace.spent(time.thread_time() - cpu)
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
            deadline += 1.0 / self.pace.hz(tabs)
            sleep = deadline - time.perf_counter()
            if sleep > 0:
                self.stop.wait(sleep)
            else:
                deadline = time.perf_counter()  # behind (a slow frame): do not try to catch up

    def close(self) -> None:
        """The tab closed: the loop ends at its next turn, and a prediction being computed gives up at its next
        chunk (physics.simulate's progress callback), so nothing of the tab keeps a core busy."""
        self.stop.set()
        self.engine.cancel_workers()


def _weakly(method):
    """``method`` (a bound method) called while its object lives, and nothing after."""
    ref = weakref.WeakMethod(method)

    def call(*args) -> None:
        bound = ref()
        if bound is not None:
            bound(*args)

    return call
