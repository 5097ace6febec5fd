"""Setting a property of a viser handle (a GUI widget or a scene node) only when its value differs: each
assignment is a message to the browser, and the panel and the scene set most of theirs every frame. Plain
Python, below the scene and the panel, which both use it."""

from __future__ import annotations


def set_if_changed(handle, name: str, value) -> None:
    if getattr(handle, name) != value:
        setattr(handle, name, value)
