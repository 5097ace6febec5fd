"""The replay's page around viser's player: a title line, the plots of theta, |K| and E as an inline PNG, the
legend and the scenario's TOML, in a box over the 3-D view. viser serializes no GUI message, so these are
written into the HTML itself; nothing in the page is fetched from anywhere (``external_refs`` checks).
"""

from __future__ import annotations

import base64
import html
import io
import re

import physics

# URLs a page may name without a browser fetching them: XML namespaces of inline SVG
NAMESPACES = ("http://www.w3.org/2000/svg", "http://www.w3.org/1999/xhtml", "http://www.w3.org/1999/xlink",
              "http://www.w3.org/XML/1998/namespace")
_URL = re.compile(r"""https?://[^\s"'<>)\\]*""")
_COLOR_SPAN = re.compile(r"&lt;span style=&#x27;color:(#[0-9a-fA-F]{6})&#x27;&gt;")
_LEGEND_BLOCK = re.compile(r"^<div [^>]*>|</div>$")  # the panel's block: this page's box has a style of its own
BOX_ID = "quasirigid-replay"

_STYLE = f"""
#{BOX_ID} {{ position: fixed; top: 8px; left: 8px; z-index: 1000; width: 380px; max-height: calc(100vh - 90px);
  overflow: auto; background: rgba(255,255,255,0.94); color: #222; border: 1px solid #ccc; border-radius: 6px;
  padding: 8px 10px; font: 13px/1.35 system-ui, sans-serif; }}
#{BOX_ID} h1 {{ font-size: 15px; margin: 0 0 4px 0; }}
#{BOX_ID} img {{ width: 100%; height: auto; display: block; margin: 4px 0; }}
#{BOX_ID} pre {{ font-size: 11px; background: #f4f4f4; padding: 4px; overflow: auto; max-height: 260px; }}
#{BOX_ID} summary {{ cursor: pointer; font-weight: 600; margin-top: 4px; }}
"""


def plot_png(trajectory: physics.Trajectory) -> bytes:
    """theta, |K| and E against t (physics.Trajectory.plot) as PNG bytes."""
    fig = trajectory.plot()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    return buf.getvalue()


def legend_page_html(legend: str) -> str:
    """The explorer's legend (app.scene.legend: one block of coloured marks and words, lines apart by <br>) as this
    page shows it: everything escaped, then only the colour spans and the line breaks let back in."""
    text = html.unescape(_LEGEND_BLOCK.sub("", legend))
    shown = _COLOR_SPAN.sub(r"<span style='color:\1'>", html.escape(text)).replace("&lt;/span&gt;", "</span>")
    return shown.replace("&lt;br&gt;", "<br>")


def page(viser_html: str, *, title: str, toml_text: str, trajectory: physics.Trajectory, legend: str = "",
         caption: str = "") -> str:
    """viser's self-contained player page (``StateSerializer.as_html()``) with the replay's box added."""
    png = base64.b64encode(plot_png(trajectory)).decode("ascii")
    legend_html = legend_page_html(legend)
    box = (f"<div id='{BOX_ID}'>"
           f"<h1>Quasirigid replay: {html.escape(title)}</h1>"
           f"<div class='caption'>{html.escape(caption)}</div>"
           "<div>Drag to turn the view; the bar at the bottom plays, pauses and scrubs.</div>"
           "<details open><summary>Plots: theta, |K| and E against t</summary>"
           f"<img alt='theta, |K| and E against t' src='data:image/png;base64,{png}'></details>"
           f"<details><summary>Legend</summary><div class='legend'>{legend_html}</div></details>"
           "<details><summary>Scenario (TOML)</summary>"
           f"<pre class='scenario'>{html.escape(toml_text)}</pre></details>"
           "</div>")
    out = re.sub(r"<title>[^<]*</title>", "", viser_html, count=1)  # viser's "Viser": ours names the replay
    out = out.replace("</head>", f"<title>Quasirigid replay: {html.escape(title)}</title><style>{_STYLE}</style>"
                      "</head>", 1)
    at = out.rindex("</body>")
    return out[:at] + box + out[at:]


def external_refs(text: str) -> list[str]:
    """http(s) URLs in the page other than XML namespaces: what a browser might try to fetch."""
    return sorted({u for u in _URL.findall(text) if not u.startswith(NAMESPACES)})
