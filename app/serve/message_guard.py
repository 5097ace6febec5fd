"""What a tab's client may set a control to: every GuiUpdateMessage is screened before viser's own handler.

viser's handler casts a value to the type the control holds (``float("abc")``, ``int({...})``) and asserts that a
property it is told to set exists; a raw client (not the viser page) that sends a slider "abc" or a dict made it
raise inside viser, printing a traceback the tab never heard of (issue 24: 405 tracebacks from one storm of
hostile values, bench/hostile.py). The page sends only ``{"value": v}`` for a control, with v of the control's
type; anything else is dropped here, the tab is told in words (``refused(message)``) and the control is sent
back the value that runs, so it shows what the server holds.

What fits a control, by what it holds now:
- a dropdown or a button group: one of its options;
- a checkbox or a button: true or false;
- a slider or a number box: a finite number (a whole one for a box that holds a whole number); a number box
  with both a min and a max set (a count, such as a sweep's points) takes only a value between them, the
  bound that keeps what it sizes on the server bounded. A slider's span is not a bound: a value past it is
  the panel's to take or refuse in words;
- a text box: a string;
- a vector or colour: as many finite numbers as it holds;
- an upload button: nothing (a file arrives by the upload messages, which app/serve/upload_cap.py bounds).

Before any of that, a frame must be a message at all (``install_frame_check``): viser's reader decoded each
frame and let any failure end the connection with a traceback (a text frame, bytes that are not msgpack, a
message type that does not exist, a field missing or of the wrong type: a camera's fov as text, an upload's
size as a list), and a message that decoded with a field of the wrong type failed later inside its handler. A
frame that is not a well-formed message of a type viser knows is dropped; the connection goes on.
"""

from __future__ import annotations

import inspect
import math
import threading
from numbers import Real

import msgspec
from viser import _messages as msgs

from .handlers import put_in_front

SHOWN_CHARS = 40  # of a refused value, in the note


def _number(v) -> bool:
    return isinstance(v, Real) and not isinstance(v, bool) and math.isfinite(float(v))


def refusal(state, updates) -> str | None:
    """Why the update ``updates`` (the message's dict) does not fit the control whose viser state is ``state``;
    None when it fits."""
    props = state.props
    label = str(getattr(props, "label", "") or "a control")
    if not isinstance(updates, dict) or set(updates) != {"value"}:
        keys = sorted(map(str, updates)) if isinstance(updates, dict) else type(updates).__name__
        return f"{label}: an update of {str(keys)[:SHOWN_CHARS]} refused; only its value can be set"
    value, held = updates["value"], state.value
    shown = repr(value)[:SHOWN_CHARS]
    options = getattr(props, "options", None)
    if options is not None:
        if isinstance(value, str) and value in options:
            return None
        listed = ", ".join(map(str, options[:6])) + (", ..." if len(options) > 6 else "")
        return f"{label}: {shown} refused; expected one of {listed}"
    if isinstance(held, bool):
        return None if isinstance(value, bool) else f"{label}: {shown} refused; expected true or false"
    if isinstance(held, (int, float)):
        if not _number(value):
            return f"{label}: {shown} refused; expected a finite number"
        step = getattr(props, "step", None)
        whole = isinstance(held, int) and isinstance(step, Real) and float(step).is_integer()
        if whole and float(value) != int(value):  # a count; a slider made with an int value may still take 0.5
            return f"{label}: {shown} refused; expected a whole number"
        lo, hi = getattr(props, "min", None), getattr(props, "max", None)
        if isinstance(props, msgs.GuiNumberProps) and lo is not None and hi is not None and not lo <= value <= hi:
            return f"{label}: {shown} refused; allowed from {lo:g} to {hi:g}"
        return None
    if isinstance(held, str):
        return None if isinstance(value, str) else f"{label}: {shown} refused; expected text"
    if isinstance(held, tuple):
        if isinstance(value, (list, tuple)) and len(value) == len(held) and all(map(_number, value)):
            return None
        return f"{label}: {shown} refused; expected {len(held)} finite numbers"
    # an upload button (its value a file, or None before one): the page sets it only by uploading, never by an
    # update, and viser's handler made a file of the value sent (a traceback for anything but a file's fields)
    return f"{label}: {shown} refused; this control is set only by uploading a file"


def screen_gui_updates(gui, refused) -> None:
    """Screen every GuiUpdateMessage this tab's client sends before viser's handler sees it (``gui`` is the tab's
    ``client.gui``): one that does not fit its control (``refusal``) is dropped, ``refused(message)`` tells the
    tab, and the control is sent the value that runs. A message for no control of this tab passes to viser,
    which ignores it. Wraps the handler list viser 1.1 keeps on the tab's connection; a viser without it is left
    as it is."""
    ws = getattr(gui, "_websock_interface", None)
    handlers = getattr(ws, "_incoming_handlers", None)
    inputs = getattr(gui, "_gui_input_handle_from_uuid", None)
    cls = getattr(msgs, "GuiUpdateMessage", None)
    if handlers is None or inputs is None or cls is None:
        return

    def make(inner):
        async def screened(client_id, message) -> None:
            uuid = message.uuid
            handle = inputs.get(uuid) if isinstance(uuid, str) else None
            if handle is not None:
                state = handle._impl
                why = refusal(state, message.updates)
                if why is not None:
                    refused(why)
                    if not state.is_button:  # the page shows the value it sent: send it the one that runs
                        ws.queue_message(cls(uuid, {"value": state.value}))
                    return
            elif not isinstance(uuid, str) or not isinstance(message.updates, dict):
                return  # malformed: for no control at all
            for cb in inner:
                out = cb(client_id, message)
                if inspect.isawaitable(out):
                    await out

        return screened

    put_in_front(handlers, cls, make)


_checked_types: dict[type, bool] = {}  # message class -> whether msgspec can check its fields (client's kinds can)
_frame_lock = threading.Lock()
_frame_check_installed = False


def well_formed(raw) -> msgs.Message | None:
    """The message one websocket frame from a client holds, or None when it holds none: a text frame, bytes that
    are not msgpack, no table with a known ``type``, or fields missing or not of the types the message declares
    (checked by msgspec against its dataclass; an int is taken for a float, nothing else is converted)."""
    if not isinstance(raw, (bytes, bytearray)):
        return None
    try:
        mapping = msgspec.msgpack.decode(raw)
    except (msgspec.DecodeError, RecursionError, ValueError):
        return None
    kind = mapping.get("type") if isinstance(mapping, dict) else None
    cls = msgs.Message._subclass_from_type_string().get(kind) if isinstance(kind, str) else None
    if cls is None:
        return None
    fields = {k: v for k, v in mapping.items() if k != "type"}
    try:
        msgspec.convert(fields, cls)
    except msgspec.ValidationError:
        return None
    except TypeError:  # a kind msgspec cannot check (only the server sends those): not a client's message
        return None
    try:
        return msgs.Message.deserialize(bytes(raw))
    except Exception:  # noqa: BLE001 - whatever viser's own decoding makes of a frame it cannot take: dropped
        return None


def install_frame_check() -> None:
    """Make viser's reader of a client's frames drop one that is not a well-formed message (``well_formed``)
    instead of ending the connection with a traceback. viser 1.1 reads every connection's frames in
    ``viser.infra._infra._message_consumer``, looked up when a connection opens: replaced once per process, for
    connections opened from then on; a viser without it is left as it is."""
    global _frame_check_installed
    from viser.infra import _infra

    with _frame_lock:
        if _frame_check_installed or not hasattr(_infra, "_message_consumer"):
            return

        async def consumer(websocket, handle_message, message_class) -> None:
            while True:
                message = well_formed(await websocket.recv())
                if message is not None and isinstance(message, message_class):
                    handle_message(message)

        _infra._message_consumer = consumer
        _frame_check_installed = True
