"""A storm of hostile messages from a raw websocket client against the real explorer: what a client that is not
the viser page can make the server do. tests/test_fuzz_websocket.py runs a short storm in CI.

Starts ``python -m app --port 0`` in a subprocess (its stdout and stderr read together), connects as
bench/load.py does (viser's wire format: msgpack out, zstd-compressed windows in), learns every input control the
tab was given from the GUI messages it receives, opens the study windows, and then, in an order drawn from one
seeded generator:

- sends every control every value of HOSTILE (wrong types, 5e-324 to 1e308, nan and infinities as numbers and
  as words, huge and negative counts, strings, tables, lists) and updates of properties that are not its value;
  between them, valid choices of the dropdowns, which drive what the storm set;
- a count far beyond what the page offers to every number box, then a change that sizes something by it
  (issue 24: the sweep's points at 1e9 and a parameter change grew the server to 3.5 GB);
- the other messages a client may send (camera, pointer, clicks, form, upload, command), with hostile fields
  and for ids that name nothing;
- junk frames: bytes that are not msgpack, text frames, msgpack that is no message or names no message type.

It reads: the tracebacks the server printed, its peak memory (VmHWM, the kernel's own peak of resident memory,
plus the largest sum of its child processes' sampled), every number the tab was sent that is not finite, whether
the storm's own connection stayed open, and whether a fresh client is still served afterwards (its controls and
a moving body).

    python -m bench hostile [--seed N] [--rounds N] [--settle S] [--out FILE]
"""

from __future__ import annotations

import asyncio
import json
import math
import os
import queue
import random
import re
import subprocess
import sys
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from bench.cli import bounded, study_parser

ROOT = Path(__file__).resolve().parent.parent
SEED = 24
START_TIMEOUT = 180.0  # s: a cold numba cache compiles the kernels first
INPUTS = ("GuiSliderMessage", "GuiNumberMessage", "GuiCheckboxMessage", "GuiTextMessage", "GuiDropdownMessage",
          "GuiButtonMessage", "GuiButtonGroupMessage", "GuiMultiSliderMessage", "GuiVector2Message",
          "GuiVector3Message", "GuiRgbMessage", "GuiRgbaMessage", "GuiUploadButtonMessage")
# values a browser never sends: wrong types, non-numbers in words, magnitudes from the smallest subnormal to the
# largest double, non-finite numbers, counts past any bound, the extremes msgpack can carry, long text
HOSTILE = ("abc", "", "nan", "inf", "-inf", "1e999", "1e-3", "1,5", {"a": 1}, {}, [1, 2, 3], [], [[1.0]], None,
           5e-324, -5e-324, 1e-300, 1e308, -1e308, float("nan"), float("inf"), float("-inf"), 0, -1, 0.5, 1e9,
           -1e9, 2 ** 63 - 1, -(2 ** 63), 2 ** 64 - 1, b"\x00\xff", "(none)", "not an option", "x" * 10_000)
CLICKS = (True, False)  # a button's or checkbox's value: sent to buttons only as hostile values, never as clicks
NOT_AN_ID = ("no-such-id", "", 12345, None, [1], {"a": 1})
INDEX = re.compile(r"\[\d+\]")  # a list index in a field's path: counted per field, not per element
FLOATS = (float("nan"), float("inf"), -1e308, 5e-324, 0.0)


def _rss(pid: int, field_name: str = "VmRSS") -> int:
    """Resident memory of process ``pid`` in bytes (``VmHWM``: its peak so far); 0 once it is gone."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith(field_name + ":"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def _children_rss(pid: int) -> int:
    """The summed resident memory of ``pid``'s child processes (a sweep's workers)."""
    try:
        kids = Path(f"/proc/{pid}/task/{pid}/children").read_text().split()
    except OSError:
        return 0
    return sum(_rss(int(k)) for k in kids)


def _traceback_blocks(text: str) -> list[list[str]]:
    """Each traceback in ``text`` as its lines, from "Traceback (most recent call last)" to the exception line."""
    lines = text.splitlines()
    out = []
    for i, line in enumerate(lines):
        if "Traceback (most recent call last)" in line:
            end = next((j for j in range(i + 1, len(lines))
                        if lines[j] and not lines[j].startswith((" ", "Traceback"))), None)
            if end is not None:
                out.append(lines[i:end + 1])
    return out


def tracebacks(text: str) -> dict[str, int]:
    """The exception line ending each traceback in ``text``, with its count."""
    out: dict[str, int] = {}
    for block in _traceback_blocks(text):
        out[block[-1][:120]] = out.get(block[-1][:120], 0) + 1
    return out


def traceback_text(text: str, limit: int = 3, width: int = 4000) -> str:
    """The first ``limit`` tracebacks in ``text`` whole (each cut to ``width`` characters): a storm's failure
    must say where it was raised, since the server's timing, unlike the storm, is not seeded."""
    return "\n\n".join("\n".join(block)[:width] for block in _traceback_blocks(text)[:limit])


@dataclass
class Served:
    """A running ``python -m app``: its address, process and the lines it has printed so far."""

    url: str
    proc: subprocess.Popen
    lines: list[str]

    @property
    def output(self) -> str:
        return "".join(self.lines)


@contextmanager
def served(timeout: float = START_TIMEOUT):
    """Start ``python -m app --port 0`` and yield it (Served) once it says it is ready; stopped on leaving."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-m", "app", "--port", "0"], cwd=ROOT, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    lines: list[str] = []
    fresh: queue.Queue = queue.Queue()

    def read():
        for line in proc.stdout:
            lines.append(line)
            fresh.put(line)

    threading.Thread(target=read, daemon=True).start()
    try:
        deadline, url = time.monotonic() + timeout, None
        while url is None and time.monotonic() < deadline and proc.poll() is None:
            try:
                m = re.search(r"ready in .*: (http://\S+)", fresh.get(timeout=1.0))
            except queue.Empty:
                continue
            url = m.group(1) if m else None
        if url is None:
            raise RuntimeError("the explorer did not start:\n" + "".join(lines))
        yield Served(url.replace("http://", "ws://").rstrip("/"), proc, lines)
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def encode(**fields) -> bytes:
    import msgspec

    return msgspec.msgpack.encode(fields)


def decode(raw: bytes) -> list[dict]:
    """The messages of one window viser sends (zstd-compressed msgpack with a 16-byte header)."""
    import msgspec
    import zstandard

    size = int.from_bytes(raw[:8], "little")
    clen = int.from_bytes(raw[8:16], "little")
    inner = zstandard.ZstdDecompressor().decompress(raw[16:16 + clen], max_output_size=size)
    return list(msgspec.msgpack.decode(inner).get("messages", ()))


def camera(**over) -> bytes:
    """What a browser sends on connecting: its camera."""
    fields = dict(wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, -3.4, 1.9), fov=1.3, near=0.01, far=1000.0,
                  image_height=720, image_width=1280, look_at=(0.0, 0.0, 0.0), up_direction=(0.0, 0.0, 1.0))
    return encode(type="ViewerCameraMessage", **{**fields, **over})


def non_finite(thing, path: str = "") -> list[str]:
    """Where ``thing`` (a decoded message) holds a float that is not finite."""
    if isinstance(thing, float):
        return [] if math.isfinite(thing) else [path]
    if isinstance(thing, dict):
        return [p for k, v in thing.items() for p in non_finite(v, f"{path}.{k}")]
    if isinstance(thing, (list, tuple)):
        return [p for i, v in enumerate(thing) for p in non_finite(v, f"{path}[{i}]")]
    return []


@dataclass
class Watch:
    """What the storm's client saw: the controls, the non-finite numbers it was sent, the server's memory."""

    pid: int
    controls: dict[str, dict] = field(default_factory=dict)
    nonfinite: dict[str, int] = field(default_factory=dict)  # message type.field -> count
    windows: int = 0
    body_moves: int = 0
    children_peak: int = 0
    rss: list[tuple[float, int]] = field(default_factory=list)  # (s since the storm began, bytes)
    t0: float = field(default_factory=time.perf_counter)

    def see(self, raw) -> None:
        if not isinstance(raw, bytes):
            return
        self.windows += 1
        for m in decode(raw):
            kind = m.get("type", "")
            if kind in INPUTS:
                props = m.get("props", {})
                self.controls[m["uuid"]] = {"type": kind, "label": str(props.get("label", "")),
                                            "options": props.get("options")}
            elif kind == "SetOrientationMessage" and str(m.get("name", "")).endswith("/body"):
                self.body_moves += 1
            for where in non_finite(m):
                key = kind + INDEX.sub("[]", where)
                self.nonfinite[key] = self.nonfinite.get(key, 0) + 1

    def sample(self) -> None:
        self.rss.append((time.perf_counter() - self.t0, _rss(self.pid)))
        self.children_peak = max(self.children_peak, _children_rss(self.pid))


async def _drain(ws, watch: Watch, seconds: float) -> None:
    end = time.perf_counter() + seconds
    while (left := end - time.perf_counter()) > 0:
        watch.sample()
        try:
            raw = await asyncio.wait_for(ws.recv(), timeout=min(left, 0.25))
        except TimeoutError:
            continue
        watch.see(raw)


def _control_messages(uuid: str, c: dict, rng: random.Random) -> list[bytes]:
    """Every hostile update of one control, in a seeded order."""
    values = [v for v in HOSTILE if not (c["type"] == "GuiButtonMessage" and isinstance(v, bool))]
    out = [encode(type="GuiUpdateMessage", uuid=uuid, updates={"value": v}) for v in values]
    out += [encode(type="GuiUpdateMessage", uuid=uuid, updates=u)
            for u in ({"not_a_prop": 1}, {"min": "abc"}, {"max": float("nan")}, {"options": None}, {},
                      {"value": 0.5, "disabled": True}, [1], "value")]
    rng.shuffle(out)
    return out


def _other_messages(controls: dict[str, dict]) -> list[bytes]:
    """Messages a client may send besides updates, with hostile fields, and updates for ids that name nothing."""
    some = next(iter(controls), "x")
    out = [encode(type="GuiUpdateMessage", uuid=u, updates={"value": 1.0}) for u in NOT_AN_ID]
    for uuid in controls:
        out += [encode(type="GuiButtonHoldMessage", uuid=uuid, held=v) for v in (None, "x", 5)]
        out += [encode(type="GuiButtonHoldMessage", uuid=uuid, frequency=v) for v in (float("nan"), "x", -1)]
        out += [encode(type="GuiFormSubmitMessage", uuid=uuid), encode(type="GuiFormDirtyMessage", uuid=uuid)]
    out += [camera(wxyz=(x, 0.0, 0.0, 0.0), position=(x, x, x), fov=x, near=x, far=x, look_at=(x, 0.0, 0.0),
                   up_direction=(0.0, 0.0, x)) for x in FLOATS]
    out += [camera(image_height=v, image_width=v) for v in (0, -1, 2 ** 63 - 1, "abc", None)]
    out += [encode(type="ViewerCameraMessage"), camera(wxyz=(1.0,)), camera(position="abc")]
    for x in (*FLOATS, "abc", None):
        out += [encode(type="ScenePointerMessage", event_type="click", ray_origin=(x, 0.0, 0.0),
                       ray_direction=(0.0, 0.0, x), screen_pos=((x, x),), modifiers=None, owner=x),
                encode(type="SceneNodeClickMessage", name="/no/such/node", instance_index=x,
                       ray_origin=(x, 0.0, 0.0), ray_direction=(0.0, 0.0, 1.0), screen_pos=(x, x), owner=x),
                encode(type="SceneNodeClickMessage", name=x, instance_index=None, ray_origin=(0.0, 0.0, 0.0),
                       ray_direction=(0.0, 0.0, 1.0), screen_pos=(0.0, 0.0)),
                encode(type="TransformControlsUpdateMessage", name="/no/such", wxyz=(x, 0.0, 0.0, 0.0),
                       position=(x, 0.0, 0.0), owner=x),
                encode(type="GuiCloseModalMessage", uuid=x),
                encode(type="CommandTriggerMessage", uuid=x),
                encode(type="LocalStorageGetItemResponseMessage", request_uuid=x, value=x, error=x),
                encode(type="GetRenderResponseMessage", payload=x)]
    for u in (*NOT_AN_ID, some):
        for size in (-1, 0, 2 ** 63 - 1, float("nan"), "abc", None):
            out.append(encode(type="FileTransferStartUpload", source_component_uuid=u, transfer_uuid=str(u),
                              filename=size, mime_type=None, part_count=size, size_bytes=size))
        out.append(encode(type="FileTransferPart", source_component_uuid=u, transfer_uuid="no-such-transfer",
                          part_index=-1, content=b"x"))
        out.append(encode(type="FileTransferPart", source_component_uuid=u, transfer_uuid=None, part_index="a",
                          content="not bytes"))
    return out


JUNK = (b"", b"\x00", b"\xc1", b"\xff" * 64, b"not msgpack at all", bytes(range(256)))


def _junk_frames(rng: random.Random) -> list:
    """Frames that are no message: not msgpack, text, msgpack of something else, no or an unknown type."""
    import msgspec

    enc = msgspec.msgpack.encode
    out: list = list(JUNK) + [rng.randbytes(rng.randrange(1, 2000)) for _ in range(20)]
    out += ["a text frame", "{\"type\": \"GuiUpdateMessage\"}", ""]
    out += [enc(v) for v in (None, 5, 1e308, "GuiUpdateMessage", [1, 2], {"uuid": "x"}, {"type": None},
                             {"type": 7}, {"type": "NoSuchMessage"}, {"type": "Message"}, {"type": ["a"]},
                             {"type": "GuiUpdateMessage"}, {"type": "GuiUpdateMessage", "uuid": "x"},
                             {"type": "GuiUpdateMessage", "uuid": "x", "updates": {}, "extra": 1},
                             {"type": "FileTransferPart"}, {"type": "ViewerCameraMessage", "wxyz": 5})]
    nested: object = 0
    for _ in range(5000):  # deeper than any parser's recursion should go
        nested = [nested]
    try:
        out.append(enc({"type": "GuiUpdateMessage", "uuid": "x", "updates": {"value": nested}}))
    except (RecursionError, ValueError):
        pass
    rng.shuffle(out)
    return out


class _Client:
    """The storm's connection: when the server closes it (a frame it could not take), a new one is opened, the
    tab's controls learnt again, and the storm goes on; the closings are counted."""

    def __init__(self, url: str, watch: Watch, settle: float):
        self.url, self.watch, self.settle = url, watch, settle
        self.ws = None
        self.closed = 0

    async def open(self) -> None:
        import viser
        from websockets.asyncio.client import connect

        self.watch.controls.clear()
        self.ws = await connect(self.url, subprotocols=[f"viser-v{viser.__version__}"], max_size=None,
                                compression=None, open_timeout=120)
        await self.ws.send(camera())
        await self.drain(self.settle)

    async def send(self, message) -> None:
        from websockets.exceptions import ConnectionClosed

        try:
            await self.ws.send(message)
        except ConnectionClosed:
            self.closed += 1
            await self.open()

    async def drain(self, seconds: float) -> None:
        from websockets.exceptions import ConnectionClosed

        try:
            await _drain(self.ws, self.watch, seconds)
        except ConnectionClosed:
            self.closed += 1
            await self.open()

    def uuid(self, kind: str, label: str) -> str | None:
        """The uuid the control of this kind and label has now (it changes when the connection is opened again)."""
        return next((u for u, c in self.watch.controls.items() if (c["type"], c["label"]) == (kind, label)), None)


async def storm(url: str, pid: int, *, seed: int = SEED, rounds: int = 1, settle: float = 6.0) -> dict:
    """Connect as a raw client, learn the tab's controls and send it the whole storm (module docstring); the
    counts of what was sent and seen, and how often the server closed the storm's connection."""
    from websockets.exceptions import ConnectionClosed

    rng = random.Random(seed)
    watch = Watch(pid)
    sent = {"updates": 0, "other": 0, "junk": 0}
    client = _Client(url, watch, settle)
    await client.open()
    controls = watch.controls

    async def update(kind, label, value, what="updates"):
        uuid = client.uuid(kind, label)
        if uuid is not None:
            await client.send(encode(type="GuiUpdateMessage", uuid=uuid, updates={"value": value}))
            sent[what] += 1

    for c in list(controls.values()):  # the study windows are built on first open: open them all
        if c["type"] == "GuiButtonMessage" and c["label"].startswith("Open the"):
            await update(c["type"], c["label"], True)
    await client.drain(settle)
    for _ in range(rounds):
        order = sorted(controls.items())
        rng.shuffle(order)
        for uuid, c in order:
            for m in _control_messages(uuid, c, rng):
                now = client.uuid(c["type"], c["label"])
                await client.send(m if now == uuid or now is None else m.replace(uuid.encode(), now.encode()))
                sent["updates"] += 1
            picks = sorted((d["type"], d["label"], tuple(d["options"])) for d in controls.values() if d["options"])
            if picks:  # a valid choice between controls, which drives what the storm set
                kind, label, options = rng.choice(picks)
                await update(kind, label, rng.choice(options))
            await client.drain(0.02)
        await client.drain(settle / 2)
    for c in list(controls.values()):  # counts past any bound, then what sizes by them
        if c["type"] == "GuiNumberMessage":
            for v in (1e9, 2 ** 62, 10 ** 18):
                await update(c["type"], c["label"], v)
    for c in list(controls.values()):
        if c["type"] == "GuiDropdownMessage" and c["options"]:
            await update(c["type"], c["label"], c["options"][0])
    await client.drain(settle / 2)
    for m in _other_messages(dict(sorted(controls.items()))):
        await client.send(m)
        sent["other"] += 1
    await client.drain(settle / 2)
    for m in _junk_frames(rng):
        await client.send(m)
        sent["junk"] += 1
    await client.drain(settle)
    try:  # still served: a ping answered
        await asyncio.wait_for(await client.ws.ping(), timeout=30)
    except (ConnectionClosed, TimeoutError):
        client.closed += 1
    await client.ws.close()
    return {"controls": len(controls), "sent": sent, "windows_received": watch.windows,
            "body_moves": watch.body_moves, "nonfinite_sent_to_tab": watch.nonfinite,
            "storm_connection_closed_by_server": client.closed, "children_rss_peak_mb": watch.children_peak / 2 ** 20,
            "rss_samples": watch.rss}


async def fresh_client(url: str, seconds: float = 20.0) -> dict:
    """A new client's first ``seconds``: the controls it was given and the body poses it received."""
    import viser
    from websockets.asyncio.client import connect

    watch = Watch(0)
    async with connect(url, subprotocols=[f"viser-v{viser.__version__}"], max_size=None, compression=None,
                       open_timeout=60) as ws:
        await ws.send(camera())
        end = time.perf_counter() + seconds
        while (left := end - time.perf_counter()) > 0 and not (watch.controls and watch.body_moves >= 10):
            try:
                watch.see(await asyncio.wait_for(ws.recv(), timeout=left))
            except TimeoutError:
                break
    return {"controls": len(watch.controls), "body_moves": watch.body_moves, "nonfinite": watch.nonfinite}


def run(seed: int = SEED, rounds: int = 1, settle: float = 6.0) -> dict:
    """Serve the explorer, storm it, then connect a fresh client; everything measured (module docstring)."""
    with served() as server:
        pid = server.proc.pid
        start_rss = _rss(pid)
        out = asyncio.run(storm(server.url, pid, seed=seed, rounds=rounds, settle=settle))
        out["fresh_client"] = asyncio.run(fresh_client(server.url))
        out["rss_start_mb"] = start_rss / 2 ** 20
        out["rss_peak_mb"] = _rss(pid, "VmHWM") / 2 ** 20
        out["server_alive"] = server.proc.poll() is None
        time.sleep(0.5)  # the last lines the server printed
        text = server.output
    out["tracebacks"] = text.count("Traceback (most recent call last)")
    out["by_exception"] = tracebacks(text)
    out["traceback_text"] = traceback_text(text)
    out["seed"], out["rounds"] = seed, rounds
    return out


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("hostile", __doc__.splitlines()[0])
    ap.add_argument("--seed", type=bounded(int, 0, 2**32 - 1), default=SEED,
                    help="seed of the storm's order and junk frames")
    ap.add_argument("--rounds", type=bounded(int, 1, 100), default=1,
                    help="times every control gets every hostile value")
    ap.add_argument("--settle", type=bounded(float, 0.5, 600.0), default=6.0,
                    help="seconds to wait for the tab, and after each stage")
    ap.add_argument("--out", type=Path, default=None, help="JSON file for the results (with the machine)")
    ap.add_argument("--note", default="", help="what was served (a commit), written into --out")
    args = ap.parse_args(argv)
    out = run(args.seed, args.rounds, args.settle)
    samples = out.pop("rss_samples")
    shown = {k: (round(v, 1) if isinstance(v, float) else v) for k, v in out.items()}
    print(json.dumps(shown, indent=1))
    if args.out is not None:
        from .machine import machine

        command = "python -m bench hostile " + " ".join(argv if argv is not None else sys.argv[2:])
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps({"command": command.strip(), "note": args.note, "machine": machine(), **shown,
                                        "rss_mb_over_time": [(round(t, 2), round(b / 2 ** 20, 1))
                                                             for t, b in samples[::10]]}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
