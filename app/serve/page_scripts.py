"""The scripts the explorer adds to viser's page, installed once before a server starts (app.share.link serves
them): the page's address, a link's scene and the reduced-motion setting handed to the tab (app.share.link); a
slider's box sending its text as typed (app.panel.typed_numbers); folder titles that open from the keyboard
(app.panel.keyboard); a fault's Undo and Reset scrolled into sight (app.panel.control_notes); a held key holding
its thruster's button (app.panel.challenge_panel)."""

from __future__ import annotations

from ..panel.challenge_panel import PAGE_SCRIPT as CHALLENGE_SCRIPT
from ..panel.control_notes import PAGE_SCRIPT as NOTES_SCRIPT
from ..panel.keyboard import PAGE_SCRIPT as KEYBOARD_SCRIPT
from ..panel.typed_numbers import PAGE_SCRIPT as TYPED_SCRIPT
from ..share.link import install as serve_with_scripts


def install() -> None:
    serve_with_scripts(TYPED_SCRIPT, KEYBOARD_SCRIPT, NOTES_SCRIPT, CHALLENGE_SCRIPT)
