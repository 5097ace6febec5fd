"""How many tabs one server serves (app.serve.capacity), on a live server with raw websocket tabs: a tab beyond
MAX_TABS is told the server is full and gets no session; in class mode the lecturer's tab is let in however many
students came first."""

from __future__ import annotations

import pytest
from test_class_mode import wait_until

from app.serve import capacity, classroom, server
from app.share.link import CLASS_KEY
from bench.class_client import Tab, run_tabs

LIMIT = 3  # MAX_TABS for these tests: a few tabs show the bound as well as a crowd does


def told_full(tab: Tab) -> bool:
    return any("is full" in t for t in tab.texts)


@pytest.fixture
def limited(monkeypatch):
    for module in (capacity, server, classroom):
        monkeypatch.setattr(module, "MAX_TABS", LIMIT)
    server.warm_up()


def test_a_tab_beyond_the_bound_is_told_and_gets_no_session(limited):
    app = server.App(host="127.0.0.1", port=0)
    url = f"ws://127.0.0.1:{app.port}"
    try:
        first = [Tab() for _ in range(LIMIT)]
        threads = [run_tabs(url, first, 60.0)]
        wait_until(lambda: len(app.sessions) == LIMIT, what="a session for each of the first tabs")
        late = [Tab(), Tab()]
        threads.append(run_tabs(url, late, 60.0))
        wait_until(lambda: all(told_full(t) for t in late), what="the late tabs told the server is full")
        note = next(t for t in late[0].texts if "is full" in t)
        assert f"serves {LIMIT} tabs at once" in note and "Reload this page" in note
        assert len(app.sessions) == LIMIT and app.stats["full"] == 2
        assert not any(told_full(t) for t in first) and all(not t.errors for t in first + late)
        assert all(sum(t.counts) == 0 for t in late)  # no frame of any run reached them
    finally:
        app.close()
    for t in threads:
        t.join(timeout=30)


def test_the_class_lets_the_lecturer_in_when_the_students_fill_it(limited):
    app = server.App(host="127.0.0.1", port=0, class_mode=True)
    room = app.classroom
    url = f"ws://127.0.0.1:{app.port}"
    try:
        students = [Tab() for _ in range(LIMIT)]
        threads = [run_tabs(url, students, 90.0)]
        wait_until(lambda: len(room.waiting) == LIMIT, what="the students waiting for the lecturer")
        extra = Tab()
        threads.append(run_tabs(url, [extra], 90.0))
        wait_until(lambda: told_full(extra), what="a student beyond the bound told the class is full")
        assert "the class is full" in next(t for t in extra.texts if "is full" in t)
        lecturer = Tab({CLASS_KEY: room.key})
        threads.append(run_tabs(url, [lecturer], 90.0))
        wait_until(lambda: len(room.views) == LIMIT + 1, what="the lecturer's view and the students' following")
        assert [v.role for v in room.views.values()].count("lecturer") == 1
        assert not told_full(lecturer) and not any(told_full(t) for t in students)
    finally:
        app.close()
    for t in threads:
        t.join(timeout=30)
