"""Just enough of viser's GUI for headless panel tests (app/studies/speed_panel.py, app/studies/sweep_panel.py,
app/panel/plots.py): widgets are recorded, and a test fires their callbacks."""

from __future__ import annotations

import numpy as np


class Handle:
    """Just enough of a viser handle: a value, options, flags and callbacks fired by the test."""

    def __init__(self, kind, label=None, value=None, **kw):
        self.kind, self.label, self.value = kind, label, value
        self.options = tuple(kw.pop("options", ()))
        self.disabled = kw.pop("disabled", False)
        self.visible = True
        self.content = kw.pop("content", "")
        self.figure = kw.pop("figure", None)
        self.callbacks = []

    def on_update(self, cb):
        self.callbacks.append(cb)

    on_click = on_update

    def fire(self):
        for cb in self.callbacks:
            cb(None)


class FakeGui:
    def __init__(self):
        self.handles = []

    def _add(self, h):
        self.handles.append(h)
        return h

    def add_markdown(self, content, **kw):
        return self._add(Handle("markdown", content=content))

    def add_dropdown(self, label, options, initial_value=None, **kw):
        return self._add(Handle("dropdown", label, initial_value, options=options))

    def add_number(self, label, initial_value, **kw):
        return self._add(Handle("number", label, initial_value))

    def add_checkbox(self, label, initial_value, **kw):
        return self._add(Handle("checkbox", label, initial_value))

    def add_button(self, label, **kw):
        return self._add(Handle("button", label, disabled=kw.get("disabled", False)))

    def add_progress_bar(self, value, **kw):
        return self._add(Handle("progress", value=value))

    def add_uplot(self, data, series, title="", visible=True, **kw):
        h = self._add(Handle("uplot", title))
        h.data, h.series, h.title, h.visible, h.scales = data, series, title, visible, kw.get("scales")
        return h

    def add_plotly(self, figure, **kw):
        h = self._add(Handle("plotly", figure=figure))
        h.kw = kw
        return h

    def button(self, prefix):
        return next(h for h in self.handles if h.kind == "button" and h.label.startswith(prefix))


def chart_finite(h: Handle) -> bool:
    """Whether a uPlot chart's plotted numbers, and its y axis's ends once the data first set them, are finite."""
    y_axis = (h.scales or {}).get("y")
    return (all(np.all(np.isfinite(np.asarray(y, dtype=float))) for y in h.data)
            and (y_axis is None or bool(np.all(np.isfinite(y_axis["range"])))))


def in_a_row(gui: FakeGui, *handles) -> bool:
    """Whether ``handles`` were added to ``gui`` one after another, in this order (where the page shows them)."""
    at = gui.handles.index(handles[0])
    return gui.handles[at:at + len(handles)] == list(handles)
