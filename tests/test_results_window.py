"""Where the study windows open (issue 24, point 5): docked at the page's left edge, so the 3-D view shrinks
beside them and its legend and momentum sphere stay in sight; a second window stacks under the first; the width
follows the view's width as the browser reports it. The browser side is tests/test_app_browser_windows.py."""

from __future__ import annotations

import pytest

from app.studies import results_window


class Window:
    def __init__(self, log):
        self.log, self.removed = log, False

    def add_tab(self, label):
        self.log.append(("tab", label))
        return object()

    def dock_left(self):
        self.log.append(("dock_left", self))

    def dock_below(self, anchor):
        if anchor.removed:
            raise ValueError("Cannot dock relative to a removed panel.")  # viser 1.1's refusal
        self.log.append(("dock_below", anchor))

    def set_width(self, w):
        self.log.append(("width", w))

    def set_height(self, h):
        self.log.append(("height", h))

    def float(self, **kw):
        self.log.append(("float", kw))


class Gui:
    def __init__(self):
        self.log, self.windows = [], []

    def add_panel(self):
        self.windows.append(Window(self.log))
        return self.windows[-1]


def test_the_first_window_docks_left_and_the_second_stacks_below_it():
    gui = Gui()
    results_window.results_tab(gui, "Sweep", 1400)
    results_window.results_tab(gui, "Speed vs accuracy", 1400)
    first, second = gui.windows
    assert ("dock_left", first) in gui.log and ("dock_below", first) in gui.log
    assert not any(kind == "float" for kind, _ in gui.log)  # never floated over the view
    assert [v for kind, v in gui.log if kind == "width"] == [round(results_window.SHARE * 1400)]


def test_a_window_opened_after_the_first_was_closed_takes_its_place():
    gui = Gui()
    results_window.results_tab(gui, "Sweep", 1024)
    gui.windows[0].removed = True
    results_window.results_tab(gui, "Speed vs accuracy", 1024)
    assert [kind for kind, _ in gui.log].count("dock_left") == 2


@pytest.mark.parametrize("canvas, width", [(None, results_window.WIDTH), (0, results_window.WIDTH),
                                           (640, results_window.MIN_WIDTH), (1024, 369), (1400, 504),
                                           (4000, results_window.WIDTH)])
def test_the_width_is_a_share_of_the_view_within_readable_bounds(canvas, width):
    assert results_window.width_for(canvas) == width


def test_a_gui_without_windows_gets_none():
    assert results_window.results_tab(object(), "Sweep", 1400) is None
