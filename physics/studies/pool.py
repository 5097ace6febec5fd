"""Local worker processes for the studies (sweeps and designs): a run in a worker ends once the study stops, and a
worker ends once the study's process has gone.

A study stopped (Stop in the explorer, Ctrl-C in the command line) keeps no result of the runs still going, and a
full run may take minutes: without a word to them the pool's shutdown waited for every one (a sweep stopped 3 s into
runs of 12-34 s returned 78 s later). The study's ``halt``, a multiprocessing Event shared with its workers, ends
their runs at the next progress callback. On dask the halt is a distributed.Event named for the study
(``DaskHalt``): cancelling a future does not stop a run already going on a worker's thread, and on a shared cluster
those runs went on for minutes after the study had stopped listening. A second Ctrl-C ends the study's process at
once (physics/__main__.py) without a word to the pool; its idle workers would wait for work forever, each keeping
the others' end of the work queue open, and hold the terminal's output: each worker watches its parent and leaves
with it.
"""

from __future__ import annotations

import importlib.util
import multiprocessing
import os
import signal
import socket
import threading
import time
import uuid
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from urllib.parse import urlsplit

from physics.core.errors import ScenarioError

PARENT_POLL_S = 0.25  # s: how often a worker looks whether the study's process still runs
DASK_TIMEOUT_S = 10  # s to reach a scheduler's address before the study is refused
DASK_HALT_POLL_S = 0.25  # s: a dask run looks at its study's halt no more often (each look asks the scheduler)
NEEDS_DISTRIBUTED = "needs dask.distributed: pip install 'dask[distributed]'"  # in the test extra only

_HALT = None  # in a worker process: its study's halt (None in the study's own process)


class Stopped(Exception):
    """A run ended because its study was stopped: no result, and not a failure of the point."""


class DaskHalt:
    """A study's halt on dask: the distributed.Event ``name``, which the study sets (``set_dask_halt``) when it
    stops. Built where the run runs (a worker), looked at no more often than every DASK_HALT_POLL_S."""

    def __init__(self, name: str):
        self.name = name
        self._event = None
        self._seen = False
        self._next = 0.0

    @staticmethod
    def new_name() -> str:
        return f"quasirigid-halt-{uuid.uuid4().hex}"

    def is_set(self) -> bool:
        if not self._seen and time.monotonic() >= self._next:
            if self._event is None:
                from distributed import Event  # on a dask worker, where distributed is installed

                self._event = Event(self.name)
            self._seen = bool(self._event.is_set())
            self._next = time.monotonic() + DASK_HALT_POLL_S
        return self._seen


def set_dask_halt(client, name: str) -> None:
    """Ends the runs of the study ``name`` still going on ``client``'s cluster at their next look."""
    from distributed import Event

    try:
        Event(name, client=client).set()
    except Exception:  # noqa: BLE001 - a scheduler gone or unreachable runs nothing of ours to end
        pass


def stopper(stop) -> Callable[[float], None]:
    """simulate's progress callback that ends the run (raising Stopped) once ``stop`` is set."""
    def progress(_fraction: float) -> None:
        if stop.is_set():
            raise Stopped
    return progress


def context(method: str | None = None):
    """``method`` if given; else fork when this process runs no other thread (the workers inherit the
    loaded compiled code and need no ``if __name__ == "__main__"`` guard in the caller's script);
    forkserver otherwise (the explorer runs server threads, and forking a threaded process can
    deadlock); spawn where neither exists."""
    methods = multiprocessing.get_all_start_methods()
    if method is not None:
        if method not in methods:
            raise ScenarioError("start_method", method, "must be one of " + ", ".join(methods))
        methods = [method]
    if "fork" in methods and (method == "fork" or threading.active_count() == 1):
        return multiprocessing.get_context("fork")
    if "forkserver" in methods:
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(["physics"])
        return ctx
    return multiprocessing.get_context("spawn")


def one_blas_thread() -> None:
    """Its BLAS (numpy.linalg, which the cheaper models' error estimates call) runs one thread. With one worker per
    core, BLAS's own thread per core in every worker made the workers fight over the cores: a design's runs took
    45 ms in two workers against 20 ms in one process (issue 26)."""
    from threadpoolctl import threadpool_limits  # here: it inspects the loaded libraries, for workers only

    threadpool_limits(1)


class HaltingPool(ProcessPoolExecutor):
    """A pool of ``workers`` processes whose runs take ``worker_halt()`` as their stop; ``close`` sets it, so the
    runs still going end at their next progress callback, and shuts the pool down."""

    def __init__(self, workers: int, ctx=None):
        ctx = ctx or context()
        self.halt = ctx.Event()
        super().__init__(max_workers=workers, mp_context=ctx, initializer=_start_worker, initargs=(self.halt,))

    def close(self) -> None:
        self.halt.set()
        self.shutdown(wait=True, cancel_futures=True)


def worker_halt():
    """In a worker of a ``HaltingPool``: the study's halt, to pass as a run's ``stop``."""
    return _HALT


def _start_worker(halt) -> None:
    """A worker leaves Ctrl-C to the study, which ends the workers' runs through ``halt`` rather than a signal that
    could land anywhere; its BLAS runs one thread, and it leaves with the study's process."""
    global _HALT
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    one_blas_thread()
    _HALT = halt
    threading.Thread(target=_end_with_parent, args=(os.getppid(),), daemon=True).start()


def _end_with_parent(parent: int) -> None:
    while os.getppid() == parent:
        time.sleep(PARENT_POLL_S)
    os._exit(1)


def scheduler_client(address: str):
    """A distributed.Client of the dask scheduler at ``address``, or a ScenarioError naming it.

    dask retries a refused connection until its timeout (30 s by default, with a bare OSError at the end), and
    an address it cannot use raised whatever its code did (an AssertionError for ``inproc://x``, a TypeError for
    ``ucx://`` without ucx): a TCP address is checked and tried once here first, and any other failure to
    connect is said in words."""
    from distributed import Client  # both callers import distributed first: missing, it fails there
    from distributed.comm.registry import backends

    # ucx is registered without ucx-py installed, and its half-built client then prints a traceback at exit
    schemes = [s for s in sorted(backends) if s != "ucx" or importlib.util.find_spec("ucp") is not None]
    allowed = (f"a scheduler's address (tcp://host:port with a port from 1 to 65535, or an "
               f"{', '.join(s for s in schemes if s != 'tcp')} address), or 'local'")
    scheme = address.split("://", 1)[0] if "://" in address else "tcp"  # dask reads a bare host:port as tcp
    if scheme not in schemes:
        raise ScenarioError("dask", address, allowed)
    where = _host_port(address, allowed) if scheme in ("tcp", "tls") else None
    try:
        if where is not None:
            socket.create_connection(where, timeout=DASK_TIMEOUT_S).close()
        return Client(address, timeout=DASK_TIMEOUT_S)
    except Exception as exc:  # noqa: BLE001 (a library's failure to connect, in words: no scheduler there, none answers)
        raise ScenarioError("dask", address, f"cannot be reached: {exc or type(exc).__name__}") from None


def _host_port(address: str, allowed: str) -> tuple[str, int]:
    """(host, port) of a tcp:// or tls:// address, or a ScenarioError saying what is allowed."""
    try:
        parts = urlsplit(address if "://" in address else "tcp://" + address)
        host, port = parts.hostname, parts.port  # a port out of 0-65535, or not a number, raises ValueError
    except ValueError:
        raise ScenarioError("dask", address, allowed) from None
    if not host or port is None or not 1 <= port <= 65535:
        raise ScenarioError("dask", address, allowed)
    return host, port
