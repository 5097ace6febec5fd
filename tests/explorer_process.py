"""``python -m app`` in a subprocess, for the tests that need the real server: started on a free port, its output
collected as it comes (a thread reads it, so a chatty server never blocks on a full pipe), and the link it prints
once it is ready. A test reads ``log`` for what the server said; ``stop`` ends it however it was started."""

from __future__ import annotations

import os
import queue
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from urllib.parse import urlsplit

import pytest

ROOT = Path(__file__).resolve().parents[1]
START_TIMEOUT = 120.0  # s: a cold numba cache compiles the kernels first
READY = re.compile(r"ready in .*: (http://\S+)")


class Explorer:
    """The explorer started with ``args`` (and ``--port 0``); ``url`` once it is ready, or the test fails with
    everything it printed. ``own_group``: in a process group of its own, which ``stop`` signals as a whole."""

    def __init__(self, *args: str, env: dict | None = None, own_group: bool = False,
                 timeout: float = START_TIMEOUT):
        self.own_group = own_group
        self.proc = subprocess.Popen([sys.executable, "-u", "-m", "app", *args, "--port", "0"], cwd=ROOT, env=env,
                                     stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                     start_new_session=own_group)
        self.log: list[str] = []
        self._lines: queue.Queue = queue.Queue()
        self._pump_thread = threading.Thread(target=self._pump, daemon=True)
        self._pump_thread.start()
        self.url = self.wait_for(READY, timeout)
        if self.url is None:
            self.proc.kill()
            self.proc.wait()
            self._pump_thread.join(timeout=10.0)
            pytest.fail("the explorer did not start:\n" + "".join(self.log))

    def _pump(self) -> None:
        for line in self.proc.stdout:
            self.log.append(line)
            self._lines.put(line)

    def wait_for(self, pattern: re.Pattern, timeout: float) -> str | None:
        """The first group of the next line printed that matches ``pattern``, or None once ``timeout`` s pass
        or the server ends."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and self.proc.poll() is None:
            try:
                m = pattern.search(self._lines.get(timeout=1.0))
            except queue.Empty:
                continue
            if m:
                return m.group(1)
        return None

    @property
    def port(self) -> int:
        return urlsplit(self.url).port

    def stop(self, sig: int = signal.SIGTERM, timeout: float = 10.0) -> int:
        """Sends ``sig`` (to the whole group if it has its own) and waits; killed if it does not end in
        ``timeout`` s. Returns the exit code."""
        if self.proc.poll() is None:
            if self.own_group:
                os.killpg(self.proc.pid, sig)
            else:
                self.proc.send_signal(sig)
            try:
                self.proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self._pump_thread.join(timeout=timeout)  # the last lines it printed, in ``log`` before the test reads it
        return self.proc.returncode

    def __enter__(self) -> Explorer:
        return self

    def __exit__(self, *exc) -> None:
        self.stop()
