"""One handler of ours in front of viser's own for a kind of message on a tab's connection (viser 1.1 keeps a list
of handlers per message class there): the GUI-update screen (app.serve.message_guard) and the upload cap
(app.serve.upload_cap) put theirs in this way."""

from __future__ import annotations


def put_in_front(handlers: dict, cls, make) -> None:
    """``handlers[cls]`` becomes ``[make(inner)]``, where ``inner`` is viser's own handlers for ``cls``. One put
    in front before is replaced, not wrapped: class mode's explore and follow build a new session on the same
    tab, and wrapped, each would add a layer every message passes through, and keep the session it was made for."""
    inner = [cb for current in handlers.get(cls, []) for cb in getattr(current, "screens", [current])]
    handler = make(inner)
    handler.screens = inner  # the handlers it screens
    handlers[cls] = [handler]
