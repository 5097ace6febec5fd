"""Movable windows (viser 1.1's ``gui.add_panel``) that hold the study panels' results with room to read them:
the sweep's chart and points, the speed-versus-accuracy chart. Each study gets its own window.

The first window stacks itself below the control panel, which the server docks at the page's right edge
(app.serve.server), in the same column; a second window stacks below the first. The 3-D view is what remains
to the left of that column, so no window covers it: the legend (which floats at the view's left), the momentum
sphere (lower left in the view) and the body stay in sight at 1024x768 as at 1400x900. (Docked at the left
edge instead, the windows left a 1024 px page a 3-D view about 250 px wide between them and the floating
control panel, with the body under the panel.) The user can drag, float, resize or minimize them. (One window
with a tab per study would hide a new result behind the other tab: viser cannot switch tabs from Python.)

A gui without ``add_panel`` (an older viser, the tests' fake) gets None: the caller then places its results
inline, in its own folder.
"""

from __future__ import annotations

import weakref

import physics

_first: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # gui -> its first results window


def results_tab(gui, label: str):
    """A new window titled ``label`` (its single tab, a context to add widgets into), or None without panels."""
    add_panel = getattr(gui, "add_panel", None)
    if add_panel is None:
        return None
    window = add_panel()
    tab = window.add_tab(label)
    first = _first.get(gui)
    if first is not None:
        try:
            window.dock_below(first)
            return tab
        except ValueError:  # the first window was closed: this one takes its place
            pass
    _first[gui] = window
    window.dock_below(gui.main_panel)  # docked right by the server; docking it here would close its folders
    return tab


def say(status, window, text: str, has_result: bool) -> None:
    """A study's news while its window shows no result (a start refused, a run under way, a run that ended with
    nothing): said in its status line and in the window too, which would otherwise go on inviting a run or show
    news that is over. The window is where the eye goes once Run is pressed: at 1024x768 it is the only part of
    the study in sight beside Run and Stop, and at 1400x900 the status line sits below the panel's fold. A window
    that shows a result keeps it; the news is then in the status line only."""
    status.content = text
    if not has_result:
        window.content = text


def blank_chart(what: str):
    """A study's chart before its first result: no axes (an empty plotly chart drew placeholder ticks, 0 to 6
    by -1 to 4, that read as data), only ``what`` will be drawn there."""
    import plotly.graph_objects as go  # plotly only once a study's panel is opened

    fig = go.Figure()
    fig.update_xaxes(visible=False)
    fig.update_yaxes(visible=False)
    fig.add_annotation(text=what, x=0.5, y=0.5, xref="paper", yref="paper", showarrow=False,
                       font={"size": 12, "color": "#777"})
    fig.update_layout(margin={"l": 10, "r": 10, "t": 10, "b": 10}, plot_bgcolor="white")
    return fig


def failure(exc: BaseException) -> str:
    """How a study's panel says what ended it: a ScenarioError in its own words (it names the parameter, the value
    and what is allowed), anything else with its kind, since a bare message ("'x'" for a KeyError) says nothing."""
    return str(exc) if isinstance(exc, physics.ScenarioError) else f"{type(exc).__name__}: {exc}"
