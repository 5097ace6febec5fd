"""Every control reachable from the keyboard (issue 25, point 4). viser's buttons, sliders, number boxes,
dropdowns and checkboxes take the focus and their keys already; its folder titles do not: a collapsed folder
(Details, Share, File, the studies) could be opened only with a mouse, and its controls were out of reach.

The page gets a script (installed like app.panel.typed_numbers' through app.share.link) that makes each folder
title a button for the keyboard: in the Tab order, named, saying whether it is open, and opened or closed with
Enter or Space, as a click does. A folder title is a Mantine Paper inside the folder's own Paper that handles
clicks (viser 1.1's client), followed by the folder's contents, which it marks aria-hidden while closed; the
script looks for titles again after the page changes, at most four times a second.
"""

from __future__ import annotations

PAGE_SCRIPT = b"""<script>/* Quasirigid (app/panel/keyboard.py): folder titles work from the keyboard */
(function () {
  var pending = false;
  function titles() {
    var out = [], papers = document.querySelectorAll("div.mantine-Paper-root > div.mantine-Paper-root");
    for (var i = 0; i < papers.length; i++)
      if (typeof papers[i].onclick === "function" && papers[i].parentElement.firstElementChild === papers[i])
        out.push(papers[i]);
    return out;
  }
  function mark() {
    pending = false;
    var found = titles();
    for (var i = 0; i < found.length; i++) {
      var t = found[i], body = t.parentElement.children[1];  /* the contents: hidden from readers while closed */
      var open = body && body.getAttribute("aria-hidden") === "false" ? "true" : "false";
      if (t.getAttribute("data-qr-key") !== "1") {
        t.setAttribute("data-qr-key", "1");
        t.setAttribute("tabindex", "0");
        t.setAttribute("role", "button");
        t.addEventListener("keydown", function (e) {
          if (e.key !== "Enter" && e.key !== " ") return;
          e.preventDefault();
          e.stopPropagation();  /* Space here opens the folder; it does not also pause the run */
          e.currentTarget.click();
        });
      }
      if (t.getAttribute("aria-expanded") !== open) t.setAttribute("aria-expanded", open);
    }
  }
  function later() { if (!pending) { pending = true; setTimeout(mark, 250); } }
  function start() {
    var what = {childList: true, subtree: true, attributes: true, attributeFilter: ["aria-hidden"]};
    new MutationObserver(later).observe(document.body, what);
    later();
  }
  if (document.body) start(); else document.addEventListener("DOMContentLoaded", start);
})();
</script>"""
