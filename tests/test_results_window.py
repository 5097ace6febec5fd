"""Where the study windows open (issue 24, point 5): in the control panel's column (the server docks the control
panel at the page's right edge; a window never moves it, which would close its open folders), so the 3-D view
is what remains beside them and no window covers its legend, sphere or body; a second window stacks under the
first. The browser side is tests/test_app_browser_windows.py."""

from __future__ import annotations

from app.studies import results_window


class Window:
    def __init__(self, log, name):
        self.log, self.name, self.removed = log, name, False

    def add_tab(self, label):
        self.log.append(("tab", label))
        return object()

    def dock_left(self):
        self.log.append(("dock_left", self.name))

    def dock_right(self):
        self.log.append(("dock_right", self.name))

    def dock_below(self, anchor):
        if anchor.removed:
            raise ValueError("Cannot dock relative to a removed panel.")  # viser 1.1's refusal
        self.log.append(("dock_below", self.name, anchor.name))

    def float(self, **kw):
        self.log.append(("float", self.name))


class Gui:
    def __init__(self):
        self.log, self.windows = [], []
        self.main = Window(self.log, "main")

    @property
    def main_panel(self):
        return self.main

    def add_panel(self):
        self.windows.append(Window(self.log, f"window {len(self.windows)}"))
        return self.windows[-1]


def test_the_first_window_stacks_below_the_control_panel_without_moving_it_and_the_second_below_the_first():
    gui = Gui()
    results_window.results_tab(gui, "Sweep")
    results_window.results_tab(gui, "Speed vs accuracy")
    docks = [entry for entry in gui.log if entry[0].startswith("dock")]
    assert docks == [("dock_below", "window 0", "main"),
                     ("dock_below", "window 1", "window 0")]
    assert not any(entry[0] == "float" for entry in gui.log)  # never floated over the view


def test_a_window_opened_after_the_first_was_closed_takes_its_place():
    gui = Gui()
    results_window.results_tab(gui, "Sweep")
    gui.windows[0].removed = True
    results_window.results_tab(gui, "Speed vs accuracy")
    assert ("dock_below", "window 1", "main") in gui.log


def test_a_gui_without_windows_gets_none():
    assert results_window.results_tab(object(), "Sweep") is None
