"""Text put into viser's markdown as it is. viser renders a markdown element's raw HTML as it comes, so whatever
came from a person (a pasted code, an uploaded file, a text typed into a slider's box) is escaped before it is
shown: HTML first, then the characters markdown reads as markup. Plain Python, below the panel and the share."""

from __future__ import annotations

import html
import re

_MARKDOWN = re.compile(r"([\\`*_{}\[\]()#+!|~])")


def plain(text: str) -> str:
    """Text shown in markdown as it is: no markup, no link, whatever it contains."""
    return _MARKDOWN.sub(r"\\\1", html.escape(text, quote=False))


__all__ = ["plain"]
