"""A slider's number box takes what a person types: the page sends the text, the server reads it.

viser 1.1.1's slider box is a Mantine NumberInput that drops the characters it does not expect before it sends
a number (``1e-3`` typed in lambda arrived as -13, ``1,5`` as 15, ``1e308`` as 1308) and clamps to the slider's
range when it loses focus. The app cannot change viser's client, so the page gets a script (``PAGE_SCRIPT``,
served in the page's head by ``app.share.link``) that keeps each slider box's keystrokes from the client's
handlers: the box holds the raw text while the user types; Enter or leaving the box sends that text, with the
slider's id, through one text control of the tab (``MAILBOX_LABEL``, its row hidden by the script), and puts
back the value that runs until the server answers. ``TypedNumbers`` reads it (``app.engine.typed``) and hands a
number to the engine like a slider's move, or says in words why it is no number. Escape leaves the box as it
was. The script touches only the number boxes beside sliders; the other number boxes are viser's as they are.

The same script rewords viser's notice "File uploaded successfully." (shown once a file has arrived, before the
server has read it): the server says under the Load button whether the file loaded or why not.
"""

from __future__ import annotations

import json

from ..engine import typed

MAILBOX_LABEL = "quasirigid typed number"  # the text control the page writes typed texts into (never shown)
MAX_MESSAGE = 400  # characters of a mailbox message: an id, a typed text of typed.MAX_TEXT and a counter
UPLOADED = "File uploaded successfully."  # viser's notice when a file has arrived (client UploadButton.tsx)
RECEIVED = "File received; whether it loaded is said under the Load button (File folder)."  # what it says instead

_SCRIPT = """<script>/* Quasirigid (app/panel/typed_numbers.py): a slider's number box sends the text as typed */
(function () {
  var MAILBOX = "@MAILBOX@", MAX_TEXT = @MAX_TEXT@, UPLOADED = "@UPLOADED@", RECEIVED = "@RECEIVED@";
  var editing = null, sent = 0, hidden = null;
  var setValue = Object.getOwnPropertyDescriptor(HTMLInputElement.prototype, "value").set;
  function sliderOf(el) {  /* the slider whose number box el is, or null */
    if (!el || el.tagName !== "INPUT" || !el.classList.contains("mantine-NumberInput-input")) return null;
    var root = el.closest(".mantine-NumberInput-root"), prev = root && root.previousElementSibling;
    return prev && prev.classList.contains("mantine-Slider-root") && prev.id ? prev : null;
  }
  function valueNow(slider) {
    var thumb = slider.querySelector("[role=slider]");
    return thumb ? thumb.getAttribute("aria-valuenow") : null;
  }
  function mailbox() {
    var labels = document.getElementsByTagName("label");
    for (var i = 0; i < labels.length; i++) {
      if (labels[i].textContent !== MAILBOX) continue;
      var row = labels[i].closest(".mantine-Flex-root");
      return row ? row.querySelector("input") : null;
    }
    return null;
  }
  function start(input) {
    var slider = sliderOf(input);
    if (slider && (!editing || editing.input !== input))
      editing = {input: input, slider: slider, text: input.value, now: valueNow(slider)};
    return slider;
  }
  function finish(input, send) {  /* send the text typed (unless Escape), show the value that runs meanwhile */
    var s = editing;
    if (!s || s.input !== input) return;
    editing = null;
    var text = input.value, now = valueNow(s.slider);
    setValue.call(input, now !== null && now !== s.now ? String(Number(now)) : s.text);
    if (!send || text === s.text) return;
    var box = mailbox();
    if (!box) return;
    sent += 1;
    setValue.call(box, JSON.stringify({id: s.slider.id, text: text.slice(0, MAX_TEXT), n: sent}));
    box.dispatchEvent(new Event("input", {bubbles: true}));
  }
  /* an edit starts at focus, at a key or before an input: the text then is the value shown */
  window.addEventListener("focusin", function (e) { start(e.target); }, true);
  window.addEventListener("beforeinput", function (e) { if (start(e.target)) e.stopImmediatePropagation(); }, true);
  ["input", "change", "paste", "cut", "keypress", "keyup", "compositionstart", "compositionupdate",
   "compositionend", "select", "wheel"].forEach(function (type) {
    window.addEventListener(type, function (e) {
      if (sliderOf(e.target)) e.stopImmediatePropagation();  /* the text stays as typed; the client never sees it */
    }, true);
  });
  window.addEventListener("keydown", function (e) {
    var input = e.target;
    if (!start(input)) return;
    e.stopImmediatePropagation();
    if (e.key === "Enter") { e.preventDefault(); finish(input, true); }
    else if (e.key === "Escape") { e.preventDefault(); finish(input, false); input.blur(); }
  }, true);
  window.addEventListener("focusout", function (e) {
    if (sliderOf(e.target)) { e.stopImmediatePropagation(); finish(e.target, true); }
  }, true);
  function hide() {  /* the mailbox's row is never shown */
    if (hidden && hidden.isConnected) return;
    var box = mailbox(), row = box && box.closest(".mantine-Flex-root");
    if (row && row.parentElement) { hidden = row.parentElement; hidden.style.display = "none"; }
  }
  function reword() {  /* a file received may yet be refused: the server says which, under the Load button */
    var said = document.getElementsByClassName("mantine-Notification-description");
    for (var i = 0; i < said.length; i++)
      if (said[i].textContent === UPLOADED) said[i].textContent = RECEIVED;
  }
  new MutationObserver(function () { hide(); reword(); }).observe(document.documentElement,
                                                                 {childList: true, subtree: true});
})();
</script>"""
PAGE_SCRIPT = (_SCRIPT.replace("@MAILBOX@", MAILBOX_LABEL).replace("@MAX_TEXT@", str(typed.MAX_TEXT))
               .replace("@UPLOADED@", UPLOADED).replace("@RECEIVED@", RECEIVED).encode())


def _id(handle) -> str | None:
    """The id viser's page gives a control (its handle's uuid); None for a stand-in without one (a test's)."""
    return getattr(getattr(handle, "_impl", None), "uuid", None)


class TypedNumbers:
    """The tab's mailbox for typed texts. ``sliders``: parameter key -> viser slider handle (read as the engine's
    slider values); ``others``: (slider, what a value typed into it requests) for the panel's other sliders (the
    time warp, a system's view factor); a value beyond such a slider's span is refused (the span is its bound)."""

    def __init__(self, gui, sliders: dict, engine, others: list | tuple = ()):
        self.engine = engine
        self.by_id = {_id(h): key for key, h in sliders.items()}  # the id the page names a slider by
        self.others = {_id(h): (h, act) for h, act in others}
        self.box = gui.add_text(MAILBOX_LABEL, "", hint=None)

        @self.box.on_update
        async def _(event):  # read as it arrives (app.panel.panel's on()): a later message would overwrite it
            if event.client is not None:
                self.received(self.box.value)

    def received(self, message) -> None:
        """One message of the page's script: ``{"id": slider id, "text": as typed, "n": count}``. A message that is
        not one (a raw client's) is dropped: it names no slider to speak beside."""
        if not isinstance(message, str) or len(message) > MAX_MESSAGE:
            return
        try:
            data = json.loads(message)
        except ValueError:
            return
        if not isinstance(data, dict) or not isinstance(data.get("text"), str) or not isinstance(data.get("id"), str):
            return
        text = data["text"][: typed.MAX_TEXT]
        key, other = self.by_id.get(data["id"]), self.others.get(data["id"])
        if key is not None:
            try:
                value, _comma = typed.read_number(text)
            except typed.Unreadable as exc:
                self.engine.refuse_typed(key, text, str(exc))
                return
            self.engine.request_value(key, value, text=text)
        elif other is not None:
            self._other(*other, text)

    def _other(self, handle, act, text: str) -> None:
        """A value typed into a slider that is no parameter: taken within its span, else refused at the top."""
        try:
            value, _comma = typed.read_number(text)
        except typed.Unreadable as exc:
            self.engine.error = f"{handle.label} = {typed.shown(text)}: {exc}; it stays {handle.value:g}"
            return
        if not handle.min <= value <= handle.max:
            self.engine.error = (f"{handle.label} = {text.strip()}: allowed from {handle.min:g} to {handle.max:g}; it "
                                 f"stays {handle.value:g}")
            return
        self.engine.error = ""
        handle.value = value  # the box shows it (the panel's callbacks skip the server's own assignment)
        act(value)
