"""The message beside the control that caused it: a note placed right under its slider, inside the slider's
folder, where the eye already is (the top of the panel is a screen away from most sliders at 1400x900).
A fault's note carries its way out: "Undo the last change" and "Reset the scene" buttons under it.

A fault's note is long, and the slider may sit at the panel's bottom edge (a folder opened there is scrolled
only far enough to show it): the page's script (PAGE_SCRIPT, installed by app.serve.page_scripts) scrolls the
panel once, when the note's last button is out of sight, to bring it to the middle of the view with the note
above it.

viser orders a container's elements by ``order`` (a float; by default a global counter, so consecutive
elements differ by at least 1): a note at the slider's order + 0.25 sits between it and the next control.
"""

from __future__ import annotations

from ..engine.edits import Note
from ..markup import plain

COLORS = {"rejected": "#c00", "fault": "#c00", "widened": "#a15c00", "read": "#555"}
UNDO_LABEL = "Undo the last change"
RESET_LABEL = "Reset the scene"

PAGE_SCRIPT = b"""<script>/* Quasirigid (app/panel/control_notes.py): a fault's way out scrolled into sight */
(function () {
  function reveal(b) {  /* a Reset button just added: each is added once, with its note */
    var r = b.getBoundingClientRect();
    if (r.top >= 0 && r.bottom <= window.innerHeight - 2) return;  /* in sight already: the panel stays put */
    b.scrollIntoView({block: "center"});  /* "nearest" left it on the edge, a fraction of a pixel out */
  }
  function added(records) {  /* only the nodes added: the readouts' many text changes cost nothing here */
    for (var i = 0; i < records.length; i++)
      for (var j = 0; j < records[i].addedNodes.length; j++) {
        var n = records[i].addedNodes[j];
        if (n.nodeType !== 1) continue;
        var found = n.matches("button") ? [n] : n.querySelectorAll("button");
        for (var k = 0; k < found.length; k++)
          if (found[k].textContent.trim() === "RESET_LABEL") setTimeout(reveal, 100, found[k]);  /* laid out */
      }
  }
  function start() { new MutationObserver(added).observe(document.body, {childList: true, subtree: true}); }
  if (document.body) start(); else document.addEventListener("DOMContentLoaded", start);
})();
</script>""".replace(b"RESET_LABEL", RESET_LABEL.encode())


class NotePlace:
    """Shows one Note at a time. ``folder_of``: slider key -> its folder handle; ``top_order``: where a note
    about no slider (or a hidden one) goes, under the panel's status; ``undo``/``reset``: the buttons'
    actions. Called from the session's loop thread only."""

    def __init__(self, gui, sliders: dict, folder_of: dict, top_order: float, undo, reset):
        self.gui, self.sliders, self.folder_of, self.top_order = gui, sliders, folder_of, top_order
        self.undo, self.reset = undo, reset
        self.shown: tuple | None = None
        self.handles: list = []

    def show(self, note: Note | None, can_undo: bool) -> None:
        want = None if note is None else (self._anchor(note.key), note.kind, note.text, can_undo)
        if want == self.shown:
            return  # each element sent costs a message: only a change is sent
        for h in self.handles:
            h.remove()
        self.handles, self.shown = [], want
        if note is None:
            return
        key = want[0]
        if key is None:
            self._add(None, self.top_order, note, can_undo)
        else:
            with self.folder_of[key]:
                self._add(key, self.sliders[key].order, note, can_undo)

    def _anchor(self, key: str | None) -> str | None:
        """The slider the note goes under, or None (the top) when it is absent, disabled or hidden."""
        if key is None or key not in self.sliders or key not in self.folder_of:
            return None
        if self.sliders[key].disabled or not self.folder_of[key].visible:
            return None
        return key

    def _add(self, key, order: float, note: Note, can_undo: bool) -> None:
        gui = self.gui
        text = f"<span style='color:{COLORS.get(note.kind, '#c00')}'>{plain(note.text)}</span>"  # it quotes typed text
        self.handles.append(gui.add_markdown(text, order=order + 0.25))
        if note.kind != "fault":
            return
        if can_undo:
            b = gui.add_button(UNDO_LABEL, color="red", order=order + 0.26,
                               hint="the parameters and the run's state of just before the last change")
            b.on_click(lambda _e: self.undo())
            self.handles.append(b)
        b = gui.add_button(RESET_LABEL, order=order + 0.27, hint="this scene's parameters as loaded, from t = 0")
        b.on_click(lambda _e: self.reset())
        self.handles.append(b)
