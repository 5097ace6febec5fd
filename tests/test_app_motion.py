"""Reduced motion (issue 25, point 4): a browser that asks for it gets a run paused at t = 0 with the reason in the
status line until Play; any other answer, a silent browser or none at all leaves the run playing. The page side
(the script that writes the browser's answer) is checked in chromium by tests/test_app_browser_controls.py."""

from __future__ import annotations

import pytest

from app.engine.engine import Engine
from app.panel import motion
from app.share import link


class Storage:
    def __init__(self, answer=None, error=None):
        self.answer, self.error, self.asked = answer, error, []

    def get_item(self, key, timeout=None):
        self.asked.append((key, timeout))
        if self.error is not None:
            raise self.error
        return self.answer


class Client:
    def __init__(self, storage):
        self.local_storage = storage


def played(eng: Engine, seconds: float = 2.0) -> Engine:
    for _ in range(int(seconds * 10)):
        eng.tick(0.1)
    return eng


def test_a_browser_asking_for_reduced_motion_gets_a_paused_run_at_zero_and_the_reason():
    eng = played(Engine())
    assert eng.playing and eng.run.t > 0
    storage = Storage(motion.REDUCE)
    m = motion.ReducedMotion(Client(storage), eng, read=False)
    m.read()
    # the panel reads the note on every frame: before the engine has applied the pause, its playing is not the user's
    assert "reduced motion" in m.status()
    eng.tick(0.1)
    assert storage.asked == [(link.MOTION_KEY, motion.READ_TIMEOUT)]
    assert not eng.playing and eng.run.t == 0.0
    assert "reduced motion" in m.status() and "Play" in m.status()
    eng.request("play")
    played(eng, 0.5)
    assert m.status() == "" and eng.run.t > 0
    eng.request("pause")
    eng.tick(0.1)
    assert m.status() == ""  # said until the first Play, not at every later pause


@pytest.mark.parametrize("storage", [Storage("no-preference"), Storage(None), Storage(error=TimeoutError("x")),
                                     Storage(error=RuntimeError("closed"))],
                         ids=["no preference", "not written", "silent", "closed"])
def test_otherwise_the_run_plays_on(storage):
    eng = played(Engine())
    m = motion.ReducedMotion(Client(storage), eng, read=False)
    m.read()
    t = eng.run.t
    played(eng, 0.5)
    assert eng.playing and eng.run.t > t and m.status() == ""


def test_the_page_script_writes_the_answer_under_the_key_read():
    assert f"{link.STORAGE_PREFIX}{link.MOTION_KEY}".encode() in link.SCRIPT
    assert b"prefers-reduced-motion: reduce" in link.SCRIPT and motion.REDUCE.encode() in link.SCRIPT
