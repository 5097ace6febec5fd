"""Whether viser still holds a tab's last frame unsent.

viser keeps each tab's outgoing messages in a buffer that its sender empties a window at a time, and a new
update of a node replaces one of the same node still waiting there. So a frame published before the sender has
taken the last one out is merged into it: the tab never sees the earlier one, and the loop spent a frame's
encoding on nothing. This happens when the server gets less of a core than its pace (app.serve.pace) counts on,
as on a machine shared with other work. The tab's loop asks ``behind()`` before it publishes and, while the
sender is behind, integrates on and publishes at its next turn instead.
"""

from __future__ import annotations


class Backlog:
    """The last frame's place in one tab's outgoing buffer, against the sender's place in it."""

    def __init__(self, client):
        connection = getattr(client, "_websock_connection", None)  # none: a tab without viser's sender
        buffer = connection.get_message_buffer() if connection is not None else None
        # a viser whose buffer keeps no send cursor: publish every frame, as before this check
        self._buffer = buffer if hasattr(buffer, "generator_cursors") and hasattr(buffer, "message_counter") else None
        self._client_id = getattr(client, "client_id", None)
        self._last = -1  # id of the last message of the last frame published

    def behind(self) -> bool:
        """The sender has not yet taken the last frame published out of the buffer."""
        if self._buffer is None:
            return False
        taken = self._buffer.generator_cursors.get(self._client_id)  # none before the sender's first window
        return taken is not None and taken < self._last

    def published(self) -> None:
        """A frame was just published: its messages are the newest in the buffer."""
        if self._buffer is not None:
            self._last = self._buffer.message_counter - 1
