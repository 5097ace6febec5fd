"""In a crowded class the following tabs get the plots at FOLLOWER_PLOT_HZ, the lecturer at every plots frame: each
tab's copy of the plots' arrays is encoded and sent on its own, which in a class of 30 was most of the server's
work. A tab that skips a plots frame draws at its next one (its flags stay raised: app.serve.class_view)."""

from __future__ import annotations

import contextlib
import time
from types import SimpleNamespace

from app.serve import classroom
from app.serve.pace import CROWD, Pace


class View:
    def __init__(self, role: str):
        self.role, self.plotted = role, 0

    def publish(self, fr, plots_now: bool, lecturer_here: bool) -> None:
        self.plotted += plots_now


def _room(students: int):
    views = {"L": View("lecturer"), **{f"s{i}": View("student") for i in range(students)}}
    drawing = SimpleNamespace(engine=SimpleNamespace(raise_flags=lambda: None), update=lambda fr, p: None)
    return SimpleNamespace(drawing=drawing, server=SimpleNamespace(atomic=contextlib.nullcontext), views=views,
                           pace=Pace(), _next_follower_plot=0.0, _gone=set()), views


def _plots_frames(students: int, frames: int, seconds: float):
    room, views = _room(students)
    start = time.perf_counter()
    for _ in range(frames):  # every frame a plots frame, spread over ``seconds``
        classroom.ClassRoom._publish(room, object(), True)
        time.sleep(seconds / frames)
    elapsed = time.perf_counter() - start  # a loaded machine's sleeps run long: the bound follows what passed
    return views["L"].plotted, [v.plotted for k, v in views.items() if k != "L"], elapsed


def test_a_crowd_of_students_gets_the_plots_at_the_follower_rate_and_the_lecturer_at_every_plots_frame():
    frames, seconds = 20, 1.0
    lecturer, students, elapsed = _plots_frames(CROWD + 1, frames, seconds)
    assert lecturer == frames
    most = classroom.FOLLOWER_PLOT_HZ * elapsed + 1
    assert most < frames  # else the test could not tell
    assert all(1 <= n <= most for n in students) and len(set(students)) == 1, students


def test_a_small_class_gets_every_plots_frame():
    lecturer, students, _ = _plots_frames(CROWD - 1, 5, 0.05)  # CROWD tabs with the lecturer: not crowded
    assert lecturer == 5 and students == [5] * (CROWD - 1)
