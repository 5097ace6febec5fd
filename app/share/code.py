"""Share codes: a scenario as a short text a student can paste, and back.

A code is ``qr1:`` followed by the scenario's TOML (``physics.Scenario.to_toml``, which round-trips bit for bit)
compressed with zlib and written in URL-safe base64 without padding, so it fits in a link's query
(``?scene=CODE``) and survives copying. Decoding takes text from anyone (a pasted code, a link, a browser's
storage), so every step is checked and bounded: the length of the text, its version, its alphabet, the inflated
size (a zip bomb stops at ``MAX_INFLATED`` bytes, like an upload), UTF-8, then the TOML parser and the
scenario's own validation. Each failure raises ``ShareCodeError`` (a ``physics.ScenarioError``) naming what was
wrong; nothing else escapes ``decode``.
"""

from __future__ import annotations

import base64
import re
import zlib
from urllib.parse import parse_qs, urlsplit

import physics

from ..engine.upload import MAX_UPLOAD_BYTES

VERSION = "qr1"
PREFIX = VERSION + ":"
MAX_INFLATED = MAX_UPLOAD_BYTES  # bytes of TOML a code may hold, as an uploaded file (a scenario is under 2 kB)
MAX_CODE_CHARS = 100_000  # a code inflating to MAX_INFLATED is well under this; more is not a code
LINK_PARAM = "scene"  # the query parameter a link carries the code in
_VERSIONED = re.compile(r"qr(\d{1,6}):", re.IGNORECASE)
_BASE64URL = re.compile(r"[A-Za-z0-9_-]*")
_SPACE = re.compile(r"\s+")


class ShareCodeError(physics.ScenarioError):
    """A share code that cannot be read: what is wrong with it, in words a user can act on."""

    def __init__(self, value: object, allowed: str):
        super().__init__("share code", _excerpt(value), allowed)


def encode(sc: physics.Scenario) -> str:
    """The share code of a scenario: ``qr1:`` + base64url(zlib(TOML))."""
    packed = zlib.compress(sc.to_toml().encode("utf-8"), 9)
    return PREFIX + base64.urlsafe_b64encode(packed).decode("ascii").rstrip("=")


def link(page_url: str, code: str) -> str:
    """A link that opens the explorer at ``page_url`` offering the scene of ``code``. The code's characters
    (letters, digits, ``-``, ``_`` and one ``:``) need no escaping in a query."""
    return f"{page_url.split('?', 1)[0].split('#', 1)[0]}?{LINK_PARAM}={code}"


def code_of(text: object) -> str:
    """The code in what a user pasted: the code itself, or a link carrying it (``...?scene=CODE``). Spaces and
    line breaks are dropped (a long code wrapped when copied)."""
    if not isinstance(text, str):
        raise ShareCodeError(f"(type {type(text).__name__})", "must be text (the code the Share button shows)")
    if len(text) > MAX_CODE_CHARS:
        raise ShareCodeError(f"({len(text)} characters)", f"must be at most {MAX_CODE_CHARS} characters; a share "
                             "code is a few hundred")
    text = _SPACE.sub("", text)
    if "?" in text and f"{LINK_PARAM}=" in text:  # a whole link pasted: take its scene parameter
        try:
            values = parse_qs(urlsplit(text).query).get(LINK_PARAM)
        except ValueError:
            values = None
        if not values:
            raise ShareCodeError(text, f"is a link without a {LINK_PARAM}= parameter; paste the code or the "
                                 "link the Share button shows")
        text = values[0]
    return text


def decode(text: object) -> physics.Scenario:
    """The scenario a share code (or a link carrying one) encodes; ShareCodeError says what is wrong."""
    code = code_of(text)
    if not code:
        raise ShareCodeError("(empty)", f"is empty; paste the code the Share button shows (it starts with {PREFIX})")
    m = _VERSIONED.match(code)
    if m is None:
        raise ShareCodeError(code, f"must start with {PREFIX} (a code from the explorer's Share button)")
    if m.group(0).lower() != PREFIX:
        raise ShareCodeError(code, f"is a version qr{int(m.group(1))} code; this explorer reads {VERSION} codes")
    body = code[m.end():].rstrip("=")  # padding is optional: encode leaves it out, a copy may add it
    inflated = _inflate(_unbase64(code, body), code)
    try:
        toml = inflated.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ShareCodeError(code, f"does not hold UTF-8 text (byte {exc.start} of its content is not); it was "
                             "not made by the Share button") from None
    try:
        return physics.Scenario.from_toml(toml)
    except physics.ScenarioError as exc:
        raise ShareCodeError(code, f"holds a scenario that is not valid: {exc}") from None
    except Exception as exc:  # the parser's own guard failed: still a message, never a traceback for the user
        raise ShareCodeError(code, f"holds a scenario that cannot be read ({type(exc).__name__})") from None


def _unbase64(code: str, body: str) -> bytes:
    if not body:
        raise ShareCodeError(code, f"has nothing after {PREFIX}; copy the whole code")
    if _BASE64URL.fullmatch(body) is None:
        i = next(i for i, ch in enumerate(body) if _BASE64URL.fullmatch(ch) is None)
        raise ShareCodeError(code, f"has {body[i]!r} at position {len(PREFIX) + i + 1}; after {PREFIX} a code is "
                             "URL-safe base64 (A-Z, a-z, 0-9, - and _)")
    if len(body) % 4 == 1:  # no byte string encodes to this length: characters are missing
        raise ShareCodeError(code, "is not whole base64 (its length is one more than a multiple of 4); it was "
                             "cut short or edited: copy the whole code")
    try:
        return base64.urlsafe_b64decode(body + "=" * (-len(body) % 4))
    except ValueError as exc:  # binascii.Error; the checks above leave none, kept for safety
        raise ShareCodeError(code, f"is not valid base64 ({exc})") from None


def _inflate(data: bytes, code: str) -> bytes:
    """zlib's inflation, stopped at MAX_INFLATED + 1 bytes: a code of a few kB can inflate to gigabytes."""
    d = zlib.decompressobj()
    try:
        out = d.decompress(data, MAX_INFLATED + 1)
    except zlib.error as exc:
        raise ShareCodeError(code, f"is not zlib-compressed data ({exc}); it was not made by the Share button, "
                             "or was edited") from None
    if len(out) > MAX_INFLATED or d.unconsumed_tail:
        raise ShareCodeError(code, f"inflates to more than {MAX_INFLATED} bytes; a scenario is a short TOML text "
                             "(under 2 kB)")
    if not d.eof:
        raise ShareCodeError(code, "is cut short (its compressed data ends early); copy the whole code")
    if d.unused_data:
        raise ShareCodeError(code, f"has {len(d.unused_data)} bytes after its compressed data; copy the code alone")
    return out


def _excerpt(value: object, n: int = 40) -> str:
    """What of the offending text is shown: its start, bounded (a pasted megabyte stays one short line)."""
    text = str(value)
    return text if len(text) <= n else text[:n] + "..."


__all__ = ["LINK_PARAM", "MAX_CODE_CHARS", "MAX_INFLATED", "PREFIX", "VERSION", "ShareCodeError", "code_of",
           "decode", "encode", "link"]
