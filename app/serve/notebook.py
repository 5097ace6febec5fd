"""The explorer inside a Jupyter notebook: ``app.show(scenario)`` serves it on a free local port and shows the page
in the output cell as an iframe, then returns at once (the tabs run in the server's threads), with a handle
whose ``stop()`` ends it.

viser 1.1.1 has no live-server ``show()`` (its ``StateSerializer.show`` and ``server.scene.show`` display a
static snapshot of the shared scene in an iframe ``srcdoc``); the explorer's scene and controls belong to each
tab, so the notebook shows the live page by its URL instead, as viser's own display does with a file.
"""

from __future__ import annotations

from pathlib import Path

import physics

from .address import shown_host
from .server import App

DEFAULT_HEIGHT = 700  # px: the control panel and the 3-D view side by side


class Explorer:
    """A running explorer: ``url``, ``app`` (app.serve.server.App: its ``server`` and the tabs' sessions),
    ``stop()``."""

    def __init__(self, app, url: str):
        self.app = app
        self.server = app.server
        self.url = url
        self.stopped = False

    def stop(self) -> None:
        """End every tab's simulation and the server (again: nothing)."""
        if not self.stopped:
            self.stopped = True
            self.app.close()

    def display(self, height: int = DEFAULT_HEIGHT) -> None:
        """Show the page in the notebook's output (outside IPython: print its URL)."""
        try:
            from IPython import get_ipython
            from IPython.display import IFrame, display
        except ImportError:
            get_ipython = None
        if get_ipython is None or get_ipython() is None:
            print(f"Quasirigid explorer: {self.url}", flush=True)
            return
        display(IFrame(self.url, width="100%", height=height))

    def __repr__(self) -> str:
        state = "stopped" if self.stopped else "running"
        return f"<Quasirigid explorer {state} at {self.url}; .stop() ends it>"

    def __enter__(self) -> Explorer:
        return self

    def __exit__(self, *exc) -> None:
        self.stop()


def show(scenario: physics.Scenario | str | Path | None = None, *, height: int = DEFAULT_HEIGHT,
         port: int = 0, host: str = "127.0.0.1", display: bool = True) -> Explorer:
    """Serve the explorer on ``scenario`` (a physics.Scenario, a TOML file's path, or None for the default scene)
    and show it inline; returns at once. ``port`` 0 picks a free one. Raises physics.ScenarioError for a
    scenario that does not run, and app.serve.address.AddressError (a ValueError) for a host or port that cannot
    be listened on, before any server starts."""
    if isinstance(scenario, (str, Path)):
        scenario = physics.Scenario.load(scenario)
    if scenario is not None and not isinstance(scenario, physics.Scenario):
        raise TypeError(f"scenario: {type(scenario).__name__} given; allowed: a physics.Scenario, a TOML file's "
                        "path or None (the default scene)")
    if scenario is not None:
        physics.LiveRun(scenario)  # a scenario that cannot run is refused here, not in the page
    explorer_app = App(host=host, port=port, scenario=scenario)
    explorer = Explorer(explorer_app, f"http://{shown_host(host)}:{explorer_app.port}")
    if display:
        explorer.display(height)
    return explorer
