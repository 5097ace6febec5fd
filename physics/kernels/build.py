"""Building the compiled kernels in a separate process, so a first start does not wait for numba.

On a machine whose numba cache is empty, the first call of the compiled integrator compiles it: 6-8 s
on an idle 2-core machine, 20-31 s under load, with the GIL held for most of it. ``start()`` runs that
compilation in a child process (``python -m physics.stepping.warm``, at a lower CPU priority) that fills
numba's on-disk cache and exits. Meanwhile ``compiled_ready()`` is False, and the live run steps with
the interpreted twins of the same kernels (``physics.kernels.interpreted``: same method, same equations, same
step sizes). When the child is done, a watcher thread loads the cached kernels into this process and
``compiled_ready()`` turns True: the live run's next call uses them, from the state it has reached.

A stamp file next to numba's cache says the build was done for these sources, this numba and this
Python: then ``start()`` sets nothing going and ``compiled_ready()`` stays True. Nothing here changes
anything for a program that never calls ``start()`` (scripts, tests, ``simulate``): they compile on
first use, as before.

``QUASIRIGID_BUILD_GATE=PATH`` (for tests): pretend the kernels are not built, and let the child
finish only once PATH exists. ``QUASIRIGID_BUILD=inline`` (for comparisons): start no build, so the first
call compiles in the calling process, as before this module.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

PENDING, READY, FAILED = "pending", "ready", "failed"
NICE = 10  # the child yields the CPU to the server and the browser: the page first, the fast path after
GATE_ENV = "QUASIRIGID_BUILD_GATE"
WARM_MODULE = "physics.stepping.warm"  # the child: python -m WARM_MODULE (a command line, not an import)
MODE_ENV = "QUASIRIGID_BUILD"


@dataclass(frozen=True)
class BuildStatus:
    """``state`` (PENDING, READY or FAILED), ``elapsed`` seconds since the build started (0 when none ran)
    and ``message`` (why it failed)."""

    state: str
    elapsed: float = 0.0
    message: str = ""


class _Build:
    def __init__(self):
        self.lock = threading.Lock()
        self.state = READY  # nothing started: compile on first use, as without this module
        self.started = 0.0
        self.finished = 0.0
        self.message = ""
        self.proc: subprocess.Popen | None = None
        self.exercise = None  # what loads the built kernels here once the child has finished


_BUILD = _Build()
_FORCED = threading.local()  # the watcher's own loading calls run compiled whatever the state


def compiled_ready() -> bool:
    """True when calling the compiled kernels costs no compilation in this process (or when no build was
    started); False while the child builds them."""
    return _BUILD.state != PENDING or getattr(_FORCED, "on", False)


def pick(function):
    """``function`` (a compiled kernel, or a Python function that calls some) when the compiled kernels are
    ready, else its interpreted twin, which runs the same code without compiling anything."""
    if compiled_ready():
        return function
    from physics.kernels.interpreted import twin

    return twin(function)


def status() -> BuildStatus:
    b = _BUILD
    if b.started == 0.0:
        return BuildStatus(b.state)
    end = b.finished if b.state != PENDING else time.perf_counter()
    return BuildStatus(b.state, end - b.started, b.message)


def _cache_dir() -> Path:
    """Where numba keeps this package's cache (physics/compiled/__pycache__, or under NUMBA_CACHE_DIR)."""
    from physics.compiled import dop853

    return Path(dop853.integrate._cache._cache_path)


def _stamp() -> Path:
    import numba

    here = Path(__file__).parent.parent / "compiled"
    digest = hashlib.sha256(f"{numba.__version__} {sys.version}".encode())
    for src in sorted(here.glob("*.py")):
        digest.update(src.name.encode() + src.read_bytes())
    return _cache_dir() / f"kernels-built-{digest.hexdigest()[:16]}.stamp"


def built() -> bool:
    """The stamp of a finished build for these sources is there (numba's cache is then warm)."""
    try:
        return _stamp().exists()
    except OSError:
        return False


def start(command: list[str] | None = None, exercise=None) -> BuildStatus:
    """Build the compiled kernels in a child process unless they are built already; returns at once.
    ``command`` replaces the child's command line (tests; by default ``python -m physics.stepping.warm``, which
    runs what the explorer runs first). ``exercise()``, if given, is called here once the child has finished,
    to load what it compiled. Calling it again while a build runs does nothing."""
    b = _BUILD
    with b.lock:
        if b.state == PENDING or os.environ.get(MODE_ENV) == "inline":
            return status()
        if command is None and built() and not os.environ.get(GATE_ENV):
            b.state = READY
            return status()
        cmd = command or [sys.executable, "-m", WARM_MODULE]
        b.exercise = exercise
        b.state, b.message, b.started, b.finished = PENDING, "", time.perf_counter(), 0.0
        try:
            b.proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        except OSError as exc:
            _finish(FAILED, f"could not start the build: {exc}")
            return status()
        threading.Thread(target=_watch, args=(b.proc,), name="kernel-build", daemon=True).start()
        return status()


def _finish(state: str, message: str = "") -> None:
    _BUILD.state, _BUILD.message, _BUILD.finished = state, message, time.perf_counter()


def _watch(proc: subprocess.Popen) -> None:
    _, err = proc.communicate()
    if proc.returncode != 0:
        # the compiled kernels then compile in this process on first use, as they did before this module
        last = (err or "").strip().splitlines()[-1:] or [f"exit status {proc.returncode}"]
        _finish(FAILED, f"the background build failed ({last[0]}); compiling in this process instead")
        return
    _FORCED.on = True
    try:
        if _BUILD.exercise is not None:
            # loads from the cache the child filled; the live run keeps stepping interpreted meanwhile
            _BUILD.exercise()
    except Exception as exc:  # noqa: BLE001 - reported in the status; the compiled path then compiles on use
        _finish(FAILED, f"loading the built kernels failed: {exc}")
        return
    finally:
        _FORCED.on = False
    _finish(READY)


def wait(timeout: float | None = None) -> BuildStatus:
    """Block until the build is no longer pending (or ``timeout`` seconds pass)."""
    end = None if timeout is None else time.perf_counter() + timeout
    while _BUILD.state == PENDING and (end is None or time.perf_counter() < end):
        time.sleep(0.02)
    return status()


def _orphaned(parent: int) -> None:
    """Exit when the process that started the build has gone (a server stopped while its build ran): the
    build is for it, and must not keep a core busy after it."""
    while os.getppid() == parent:
        time.sleep(0.2)
    os._exit(3)


def main(exercise) -> int:
    """The child's work: run ``exercise()`` compiled (filling numba's cache), at a lower priority, ending with
    the process that started it; then stamp the cache as built."""
    try:
        os.nice(NICE)
    except (OSError, AttributeError):
        pass
    threading.Thread(target=_orphaned, args=(os.getppid(),), daemon=True).start()
    gate = os.environ.get(GATE_ENV)
    while gate and not Path(gate).exists():
        time.sleep(0.05)
    build_here(exercise)
    return 0


def build_here(exercise) -> None:
    """Compile (or load) the kernels ``exercise()`` runs, in this process, and stamp numba's cache as built."""
    exercise()
    _stamp().write_text("numba's cache holds the explorer's kernels for these sources\n")
