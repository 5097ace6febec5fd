"""A storm of hostile values from a raw websocket client to every control of one tab, counting the server's
tracebacks and its peak memory: what a client that is not the viser page can make the server do.

Starts ``python -m app`` on a free port (its stderr to a file), connects as bench/load.py does (viser's wire format:
msgpack out, zstd-compressed windows in), learns every input control the tab was given from the GUI messages it
receives, and sends each control every value of HOSTILE as a GuiUpdateMessage, then a few valid dropdown choices.
Reports the tracebacks the server printed, its peak RSS and the notes the tab was shown.

    python -m bench hostile [--rounds N] [--settle S]
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
INPUTS = ("GuiSliderMessage", "GuiNumberMessage", "GuiCheckboxMessage", "GuiTextMessage", "GuiDropdownMessage",
          "GuiButtonMessage", "GuiButtonGroupMessage", "GuiMultiSliderMessage", "GuiVector2Message",
          "GuiVector3Message", "GuiRgbMessage", "GuiRgbaMessage")
# the values a browser never sends: wrong types, non-numbers, huge counts, non-finite numbers in words
HOSTILE = ("abc", "", "nan", "inf", "-inf", "1e999", {"a": 1}, [1, 2, 3], None, True, 1e9, -1e9, 1e308, -1e308,
           2 ** 63 - 1, -(2 ** 63), 0, 1e-300, "(none)", "not an option")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _rss(pid: int) -> int:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def _decode(raw: bytes) -> list[dict]:
    import msgspec
    import zstandard

    size = int.from_bytes(raw[:8], "little")
    clen = int.from_bytes(raw[8:16], "little")
    inner = zstandard.ZstdDecompressor().decompress(raw[16:16 + clen], max_output_size=size)
    return list(msgspec.msgpack.decode(inner).get("messages", ()))


async def _storm(url: str, rounds: int, settle: float, pid: int, peak: list[int]) -> dict:
    import msgspec
    import viser
    from websockets.asyncio.client import connect

    controls: dict[str, dict] = {}
    notes: list[str] = []
    sent = 0

    def enc(**fields) -> bytes:
        return msgspec.msgpack.encode(fields)

    async def drain(ws, seconds: float) -> None:
        end = time.perf_counter() + seconds
        while (left := end - time.perf_counter()) > 0:
            peak[0] = max(peak[0], _rss(pid))
            try:
                raw = await asyncio.wait_for(ws.recv(), timeout=min(left, 0.5))
            except TimeoutError:
                continue
            if not isinstance(raw, bytes):
                continue
            for m in _decode(raw):
                kind = m.get("type", "")
                if kind in INPUTS:
                    controls[m["uuid"]] = {"type": kind, "label": m.get("props", {}).get("label", ""),
                                           "options": m.get("props", {}).get("options")}
                elif kind == "GuiUpdateMessage":
                    content = m.get("updates", {}).get("content")
                    if isinstance(content, str) and "refused" in content and content not in notes[-5:]:
                        notes.append(content)

    async with connect(url, subprotocols=[f"viser-v{viser.__version__}"], max_size=None, compression=None,
                       open_timeout=120) as ws:
        await ws.send(enc(type="ViewerCameraMessage", wxyz=(1.0, 0.0, 0.0, 0.0), position=(3.0, -3.4, 1.9), fov=1.3,
                          near=0.01, far=1000.0, image_height=720, image_width=1280, look_at=(0.0, 0.0, 0.0),
                          up_direction=(0.0, 0.0, 1.0)))
        await drain(ws, settle)
        for uuid, c in list(controls.items()):  # the study panels are built on first open: open them all
            if c["type"] == "GuiButtonMessage" and str(c["label"]).startswith("Open the"):
                await ws.send(enc(type="GuiUpdateMessage", uuid=uuid, updates={"value": True}))
        await drain(ws, settle)
        for _ in range(rounds):
            for uuid, c in list(controls.items()):
                if c["type"] in ("GuiButtonMessage",):
                    continue  # a button's value is a click: nothing hostile to send
                for v in HOSTILE:
                    await ws.send(enc(type="GuiUpdateMessage", uuid=uuid, updates={"value": v}))
                    sent += 1
                await ws.send(enc(type="GuiUpdateMessage", uuid=uuid, updates={"not_a_prop": 1}))
                await ws.send(enc(type="GuiUpdateMessage", uuid=uuid, updates={"min": "abc"}))
                sent += 2
                await drain(ws, 0.05)
            for uuid, c in list(controls.items()):  # then valid choices, which drive what the storm set
                if c["type"] == "GuiDropdownMessage" and c["options"]:
                    await ws.send(enc(type="GuiUpdateMessage", uuid=uuid, updates={"value": c["options"][-1]}))
                    sent += 1
            await drain(ws, settle)
        # a count far beyond what the browser offers, then a change that sizes something by it (issue 24: the
        # sweep's points at 1e9 and a parameter change grew the server to 3.5 GB)
        for uuid, c in list(controls.items()):
            if c["type"] == "GuiNumberMessage" and "points" in str(c["label"]):
                await ws.send(enc(type="GuiUpdateMessage", uuid=uuid, updates={"value": 1e9}))
                sent += 1
        for uuid, c in list(controls.items()):
            if c["type"] == "GuiDropdownMessage" and "parameter" in str(c["label"]) and c["options"]:
                await ws.send(enc(type="GuiUpdateMessage", uuid=uuid, updates={"value": c["options"][0]}))
                sent += 1
        await drain(ws, settle)
    return {"controls": len(controls), "messages_sent": sent, "notes": notes}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m bench hostile", description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=1, help="times every control gets every hostile value")
    ap.add_argument("--settle", type=float, default=8.0, help="seconds to wait for the tab, and after a round")
    args = ap.parse_args(argv)
    port = _free_port()
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    with tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen([sys.executable, "-m", "app", "--port", str(port)], cwd=ROOT, env=env,
                                stdout=subprocess.DEVNULL, stderr=err)
        peak = [0]
        try:
            deadline = time.monotonic() + 180
            while time.monotonic() < deadline:
                try:  # a plain page request: a bare TCP probe would itself print a handshake traceback
                    urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=5).close()
                    break
                except OSError:
                    time.sleep(0.5)
            start_rss = _rss(proc.pid)
            out = asyncio.run(_storm(f"ws://127.0.0.1:{port}", args.rounds, args.settle, proc.pid, peak))
        finally:
            proc.terminate()
            proc.wait(timeout=30)
        err.seek(0)
        text = err.read()
    lines = text.splitlines()
    errors = {}
    for i, line in enumerate(lines):  # the exception line that ends each traceback
        if line.startswith("Traceback (most recent call last)"):
            for nxt in lines[i + 1:]:
                if nxt and not nxt.startswith((" ", "Traceback")):
                    errors[nxt[:100]] = errors.get(nxt[:100], 0) + 1
                    break
    print(json.dumps({**out, "notes": out["notes"][-8:], "tracebacks": text.count("Traceback (most recent call last)"),
                      "by_exception": errors, "rss_start_mb": round(start_rss / 2 ** 20),
                      "rss_peak_mb": round(peak[0] / 2 ** 20)}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
