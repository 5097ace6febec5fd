"""Class mode (issue 25, point 1; app/serve/classroom.py): one run, driven by the lecturer's tab, followed by every
student's. Headless: a real viser server in this process and raw websocket tabs (bench/class_client.py) that
answer the server's reads of their storage as the page's script would have filled it. Asserted as counts and
equalities, never wall times: the students wait for the lecturer; each follows the lecturer's edit and pause;
a student's raw message for the lecturer's controls changes nothing; a late joiner starts at the present t with
the plots from t = 0; "Explore from here" starts at the class state and "Follow the class" comes back; the
class engine ticks once per frame however many tabs follow."""

from __future__ import annotations

import re
import subprocess
import sys
import time
import weakref
from pathlib import Path

import numpy as np
import pytest

from app.serve.classroom import FOLLOW
from app.share.link import CLASS_KEY
from bench.class_client import Tab, run_tabs

ROOT = Path(__file__).resolve().parent.parent
WAIT_S = 120.0  # the longest a condition is waited for (a loaded machine builds a lecturer's panel slowly)
TAB_SECONDS = 600.0  # the raw tabs stay connected this long at most; the server's close ends them sooner


def wait_until(condition, timeout: float = WAIT_S, what: str = "") -> None:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return
        time.sleep(0.05)
    raise AssertionError(f"not within {timeout:g} s: {what}")


def gui_update(handle, value) -> dict:
    """The message a page sends when its control ``handle`` takes ``value`` (a click: True)."""
    return dict(type="GuiUpdateMessage", uuid=handle._impl.uuid, updates={"value": value})


# ---- a class on a live server, raw tabs ---------------------------------------------------------------
@pytest.fixture(scope="module")
def klass():
    from app.serve.server import App, warm_up

    warm_up()
    app = App(host="127.0.0.1", port=0, class_mode=True)
    room = app.classroom
    url = f"ws://127.0.0.1:{app.port}"
    early = Tab()  # a student before the lecturer
    threads = [run_tabs(url, [early], TAB_SECONDS)]
    wait_until(lambda: len(room.waiting) == 1, what="the early student waits")
    assert room.engine is None and not room.views  # no class run before the lecturer opens it
    lecturer, student = Tab({CLASS_KEY: room.key}), Tab({CLASS_KEY: room.key[:-1] + "x"})  # a wrong key
    threads.append(run_tabs(url, [lecturer, student], TAB_SECONDS))
    wait_until(lambda: len(room.views) == 3, what="three views")
    tabs = dict(early=early, lecturer=lecturer, student=student)
    try:
        yield app, room, tabs
    finally:
        app.close()


def ellipsoid(drawing):
    """The scale of a drawing's inertia ellipsoid, or None while the loop redraws it."""
    h = drawing.handles.get("ellipsoid")
    return None if h is None else np.array(h.scale)


def views(room, role):
    return [v for v in list(room.views.values()) if v.role == role]


def test_the_lecturers_key_alone_makes_the_lecturer(klass):
    _app, room, tabs = klass
    assert sorted(v.role for v in room.views.values()) == ["lecturer", "student", "student"]
    assert all(t.storage_reads >= 1 for t in tabs.values())  # each tab was asked for its class parameter
    assert room.is_lecturer(room.key) and not room.is_lecturer(room.key[:-1]) and not room.is_lecturer(None)
    assert not views(room, "student")[0].client.gui._gui_input_handle_from_uuid.keys() & {
        h._impl.uuid for h in views(room, "lecturer")[0].panel.sliders.values()}


def test_followers_show_the_lecturers_edit_and_pause(klass):
    _app, room, tabs = klass
    lecturer = views(room, "lecturer")[0]
    a0 = room.engine.scenario.body.A
    a1 = 1.25 if a0 != 1.25 else 1.3
    shapes = {name: len(t.shapes) for name, t in tabs.items()}
    tabs["lecturer"].send(gui_update(lecturer.panel.sliders["body.A"], a1))
    wait_until(lambda: room.engine.scenario.body.A == a1, what="the lecturer's edit applied")
    wait_until(lambda: all(len(t.shapes) > shapes[name] for name, t in tabs.items()),
               what="every tab received the body drawn anew")
    assert np.allclose(ellipsoid(room.drawing), room.engine.ellipsoid() * room.drawing.k)  # the edited body
    tabs["lecturer"].send(gui_update(lecturer.panel.playbar.buttons, "Pause"))
    wait_until(lambda: not room.engine.playing, what="the lecturer's pause applied")
    wait_until(lambda: all("· paused" in v.panel.status_md.content for v in views(room, "student")),
               what="every follower says paused")
    wait_until(lambda: all(v.panel.readout_md.content == lecturer.panel.readout_md.content
                           for v in views(room, "student")), what="the followers' readouts are the lecturer's")
    tabs["lecturer"].send(gui_update(lecturer.panel.playbar.buttons, "Play"))
    wait_until(lambda: room.engine.playing, what="playing again")


def test_a_students_raw_messages_cannot_change_the_class_run(klass):
    _app, room, tabs = klass
    lecturer = views(room, "lecturer")[0]
    seq, a0 = room.engine.change_seq, room.engine.scenario.body.A
    frames = room.frames
    for tab in (tabs["student"], tabs["early"]):  # the lecturer's controls' ids, sent from a student's tab
        tab.send(gui_update(lecturer.panel.sliders["body.A"], 1.5))
        tab.send(gui_update(lecturer.panel.playbar.buttons, "Reset"))
        tab.send(gui_update(lecturer.panel.preset, lecturer.panel.preset_names[-1]))
    wait_until(lambda: room.frames > frames + 30, what="thirty frames after the students' messages")
    assert room.engine.change_seq == seq and room.engine.scenario.body.A == a0
    tabs["lecturer"].send(gui_update(lecturer.panel.sliders["body.A"], 1.5))  # the same message, the lecturer's
    wait_until(lambda: room.engine.scenario.body.A == 1.5, what="the lecturer's message applied")


def test_a_late_joiner_starts_at_the_present_with_the_plots_from_zero(klass):
    app, room, _tabs = klass
    wait_until(lambda: room.engine.run.t > 1.0, what="the class run past t = 1 s")
    t_join = room.engine.run.t
    late = Tab()
    before = set(room.views)
    run_tabs(f"ws://127.0.0.1:{app.port}", [late], TAB_SECONDS)
    wait_until(lambda: set(room.views) - before, what="the late joiner's view")
    view = room.views[next(iter(set(room.views) - before))]
    wait_until(lambda: view.published > 0 and len(view.panel.plots.handles["K"].data[0]) > 1,
               what="its first frames")
    t = view.panel.plots.handles["K"].data[0]
    assert t[0] == 0.0 and t[-1] >= t_join  # the plots from t = 0 to the present
    counts = sum(late.counts)
    wait_until(lambda: sum(late.counts) > counts + 10, what="the shared scene's body turning in the late tab")


def test_explore_from_here_starts_at_the_class_state_and_follow_returns(klass):
    _app, room, tabs = klass
    view = views(room, "student")[0]
    cid = view.client.client_id
    tabs["lecturer"].send(gui_update(views(room, "lecturer")[0].panel.playbar.buttons, "Pause"))
    wait_until(lambda: not room.engine.playing, what="paused: the class state stays put")
    time.sleep(0.5)
    t_class, toml = room.engine.run.t, room.engine.scenario.to_toml()
    state = room.engine.run.last.table().copy()
    for t in tabs.values():  # a click on this view's button: only the tab that has it is heard
        t.send(gui_update(view.panel.explore, True))
    wait_until(lambda: cid in room.explorers, what="the student's own run")
    session = room.explorers[cid]
    assert cid not in room.views
    assert session.engine.scenario.to_toml() == toml and session.engine.run.t >= t_class
    if not session.engine.playing:  # paused as the class was: the very state
        assert np.array_equal(session.engine.run.last.table(), state)
    session.engine.request_value("body.A", 1.1)  # the student's own edit
    wait_until(lambda: session.engine.scenario.body.A == 1.1, what="the student's edit in the student's run")
    assert room.engine.scenario.body.A != 1.1 and room.engine.run.t == t_class  # the class run untouched
    back = session.follow_button
    assert back.label == FOLLOW
    for t in tabs.values():
        t.send(gui_update(back, True))  # only the tab that has the button is heard
    wait_until(lambda: cid in room.views and cid not in room.explorers, what="following again")
    ended = weakref.ref(session)  # the run it left is cyclic garbage: the server's collector frees it
    session = back = None  # (the lambdas above hold the names, not the objects)
    wait_until(lambda: ended() is None, timeout=30.0, what="the student's own run freed")
    tabs["lecturer"].send(gui_update(views(room, "lecturer")[0].panel.playbar.buttons, "Play"))


def test_the_class_engine_ticks_once_per_frame_however_many_follow(klass):
    _app, room, _tabs = klass
    ticks = [0]
    tick = room.engine.tick

    def counted(dt):
        ticks[0] += 1
        return tick(dt)

    room.engine.tick = counted
    try:
        wait_until(lambda: ticks[0] > 0, what="a tick")
        frames0, ticks0 = room.frames, ticks[0]
        published0 = {cid: v.published for cid, v in room.views.items()}
        wait_until(lambda: room.frames > frames0 + 60, what="sixty frames")
        frames, n = room.frames - frames0, ticks[0] - ticks0
        published = {cid: v.published - published0[cid] for cid, v in room.views.items() if cid in published0}
    finally:
        del room.engine.tick
    assert len(published) >= 3  # the lecturer and at least two students followed meanwhile
    assert abs(n - frames) <= 1  # one tick a frame (a frame may be counted between the two reads)
    assert all(abs(p - frames) <= 1 for p in published.values())  # and each view was published each frame


def test_python_m_app_class_prints_the_two_links():
    proc = subprocess.Popen([sys.executable, "-m", "app", "--class", "--port", "0"], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    lines: list[str] = []
    try:
        for line in proc.stdout:
            lines.append(line.rstrip("\n"))
            if line.startswith("students:"):
                break
    finally:
        proc.kill()
        proc.wait()
    lecturer = [x for x in lines if x.startswith("lecturer:")]
    students = [x for x in lines if x.startswith("students:")]
    assert len(lecturer) == 1 and len(students) == 1, lines
    m = re.fullmatch(r"lecturer: (http://127\.0\.0\.1:\d+)/\?class=([A-Za-z0-9_-]{22,})", lecturer[0])
    assert m, lecturer[0]
    assert students[0] == f"students: {m.group(1)}/"  # the same server; no key


def test_every_node_of_the_class_scene_hides_with_its_one_parent(klass):
    """A student exploring hides the class scene in their tab with one update of CLASS_NODES: every node the class
    drawing made (its light, grid, sphere, a compare run's second body) must sit under it, not beside it."""
    from app.serve.class_view import CLASS_NODES

    app, room, tabs = klass
    tabs["lecturer"].send(gui_update(views(room, "lecturer")[0].panel.challenge.start, True))  # a race: compare on
    wait_until(lambda: room.engine.challenge is not None and room.drawing.compare.nodes, what="the race drawn")
    names = [n for n in list(app.server.scene._handle_from_node_name) if n.startswith("/sclass")]
    (parent,) = CLASS_NODES
    assert any("_cmp" in n for n in names) and any("_sphere" in n for n in names)
    assert all(n == parent or n.startswith(parent + "/") for n in names), names
    tabs["lecturer"].send(gui_update(views(room, "lecturer")[0].panel.challenge.end, True))
    wait_until(lambda: room.engine.challenge is None, what="the race ended")
