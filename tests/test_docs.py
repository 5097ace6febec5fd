"""Every shell command and Python snippet in README.md and docs/*.md runs, so none can go stale.

Fenced blocks are found in README.md and every docs/*.md (new pages are picked up automatically) and run in
document order, one scratch directory per page (so a snippet may use a file an earlier block of the same page
wrote). The scratch directory holds symlinks to the repository's files and folders except the Python packages,
which are imported from the repository itself (PYTHONPATH). A relative path in a command therefore reads
the repository, and a file written at the top level (``--out traj.csv``) stays in the scratch directory; a
path into a repository folder (``docs/img/...``) reaches the repository, so such a command needs ``run=``.

- ``python`` blocks run as ``python -`` in the scratch directory and must exit 0.
- ``bash``/``sh``/``shell`` blocks: each line (``\\`` continues it) is split at ``&&`` into commands; a
  ``console`` block's commands are its lines starting with ``$``. Each command must exit 0, except that:
  - ``python -m app ...`` (or any command of a block annotated ``server``) is a server: it is started, must
    print ``ready`` within the timeout, and is then terminated; ``python -m app record ...`` writes a file and
    exits, so it runs as any command. ``--port 0`` is added when no port is given,
    so it never collides with an explorer already running.
  - ``pip install ARGS`` (also ``python -m pip``) is not executed: ``pip install --dry-run --no-deps ARGS``
    runs from the repository root instead (it builds the package metadata, so a broken pyproject.toml or a
    missing extra fails), and every extra named in ``.[a,b]`` must exist in pyproject.toml.
  - ``apt-get install ARGS`` (with or without ``sudo``) runs as ``apt-get install -s ARGS`` (simulate: the
    package names must exist; needs no root).
  - ``python -m pytest ARGS`` runs as ``python -m pytest --collect-only ARGS``: the tests themselves run in
    CI; here the command must name tests that exist and collect.
- ``toml`` blocks with a ``[run]`` or ``[body]`` table must load as a physics.Scenario; other tagged blocks
  (``text``, ``csv``...) are not code. An untagged block fails ``test_every_block_is_tagged_and_its_annotation_parses``.

Annotations: an HTML comment on the line before the fence (invisible when rendered, visible in the source),

    <!-- docs-test: slow timeout=300 run="python -m bench figures --out {tmp}/figs" -->

- ``timeout=SECONDS``: per command (default 60 s; servers 180 s, since a cold numba cache compiles first);
- ``slow``: the block's test is marked slow (slow tests still run in CI and count towards its budget);
- ``server``: every command of the block is a server (see above); ``ready="REGEX"`` changes what it must print;
- ``run="COMMANDS"``: run this instead of the block, for a command too costly or too invasive to run as shown
  (e.g. one that rewrites docs/img); ``{tmp}`` is the scratch directory. The page must say, next to the
  block, how the two relate.

Budget: the whole file takes about 1.5 min on 2 shared cores (the figures command about 40 s, each pip
dry-run about 10 s, each server about 5 s once numba's cache is warm).
"""

from __future__ import annotations

import dataclasses
import os
import queue
import re
import shlex
import signal
import subprocess
import sys
import threading
import time
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
PACKAGES = ("physics", "app", "bench")  # imported from ROOT, never through a symlink (numba's cache keys on paths)
SHELL = ("bash", "sh", "shell", "console")
RUN = SHELL + ("python",)
NOT_CODE = ("text", "toml", "csv", "json", "yaml", "ini", "diff", "output", "math")
OPTIONS = ("slow", "server", "timeout", "run", "ready")
TIMEOUT = 60.0  # s per command
SERVER_TIMEOUT = 180.0  # s to print "ready"
READY = r"\bready\b"

FENCE = re.compile(r"^( {0,8})(```+|~~~+)\s*([\w+-]*)[^\n]*$")  # indented: a block inside a list item
ANNOTATION = re.compile(r"^\s*<!--\s*docs-test:(.*?)-->\s*$")


@dataclasses.dataclass(frozen=True)
class Block:
    page: Path
    line: int  # 1-based line of the opening fence
    lang: str
    code: str
    options: tuple[tuple[str, str], ...]
    annotation_error: str = ""

    @property
    def id(self) -> str:
        return f"{self.page.relative_to(ROOT)}:{self.line}-{self.lang or 'untagged'}"

    def opt(self, name: str, default=None):
        return dict(self.options).get(name, default)


def parse_annotation(text: str) -> tuple[tuple[tuple[str, str], ...], str]:
    try:
        words = shlex.split(text)
    except ValueError as exc:
        return (), f"cannot parse annotation {text!r}: {exc}"
    opts = []
    for w in words:
        name, _, value = w.partition("=")
        if name not in OPTIONS:
            return (), f"unknown docs-test option {name!r} (known: {', '.join(OPTIONS)})"
        opts.append((name, value))
    return tuple(opts), ""


def _dedent(line: str, indent: int) -> str:
    """A block's line without the fence's own indentation (a block inside a list item)."""
    n = len(line) - len(line.lstrip(" "))
    return line[min(n, indent):]


def blocks_of(page: Path) -> list[Block]:
    lines = page.read_text(encoding="utf-8").splitlines()
    out, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, fence, lang, start = len(m.group(1)), m.group(2), m.group(3).lower(), i
        j = i + 1
        while j < len(lines) and not lines[j].strip().startswith(fence[0] * len(fence)):
            j += 1
        k = start - 1
        while k >= 0 and not lines[k].strip():
            k -= 1
        opts, err = (), ""
        if k >= 0 and (a := ANNOTATION.match(lines[k])):
            opts, err = parse_annotation(a.group(1))
        code = "\n".join(_dedent(ln, indent) for ln in lines[start + 1:j])
        out.append(Block(page, start + 1, lang, code, opts, err))
        i = j + 1
    return out


BLOCKS = [b for p in PAGES for b in blocks_of(p)]


def test_the_pages_have_blocks_to_run():
    assert sum(b.lang in RUN for b in BLOCKS) >= 5
    assert any(b.page.name == "README.md" for b in BLOCKS)


def test_every_block_is_tagged_and_its_annotation_parses():
    bad = [f"{b.id}: untagged (say ```bash, ```python, ```text...)" for b in BLOCKS if not b.lang]
    bad += [f"{b.id}: language {b.lang!r} is neither run nor known as not code" for b in BLOCKS
            if b.lang and b.lang not in RUN + NOT_CODE]
    bad += [f"{b.id}: {b.annotation_error}" for b in BLOCKS if b.annotation_error]
    bad += [f"{b.id}: run= on a block that is not run" for b in BLOCKS if b.opt("run") and b.lang not in SHELL]
    assert not bad, "\n".join(bad)


def test_the_parser_reads_annotations_and_commands(tmp_path):
    page = tmp_path / "p.md"
    page.write_text("text\n\n<!-- docs-test: slow timeout=5 run=\"echo {tmp}\" -->\n\n```bash\nls && \\\n  pwd\n"
                    "```\n\n```\nuntagged\n```\n\n<!-- docs-test: nonsense -->\n```python\nx = 1\n```\n\n"
                    "1. a step:\n\n   ```python\n   if True:\n       y = 2\n   ```\n")
    a, b, c, d = blocks_of(page)
    assert d.lang == "python" and d.code == "if True:\n    y = 2"
    assert (a.lang, a.line, a.opt("timeout"), a.opt("run"), "slow" in dict(a.options)) == ("bash", 5, "5",
                                                                                            "echo {tmp}", True)
    assert commands(a) == ["ls", "pwd"]
    assert b.lang == "" and "nonsense" in c.annotation_error
    console = dataclasses.replace(a, lang="console", code="$ python -m app --port 0\nready\n$ ls # list")
    assert commands(console) == ["python -m app --port 0", "ls # list"]


# ---- running -----------------------------------------------------------------------------------------

def commands(block: Block) -> list[str]:
    text = block.code.replace("\\\n", " ")
    lines = text.splitlines()
    if block.lang == "console":
        lines = [ln.strip()[1:].strip() for ln in lines if ln.strip().startswith("$")]
    out = []
    for ln in lines:
        if not ln.strip() or ln.strip().startswith("#"):
            continue
        out += [c.strip() for c in re.split(r"\s&&\s", ln) if c.strip()]
    return out


def bare(cmd: str) -> list[str]:
    """The command's words without a trailing comment."""
    return shlex.split(cmd, comments=True)


def env() -> dict:
    e = dict(os.environ)
    e["PYTHONPATH"] = str(ROOT) + (os.pathsep + e["PYTHONPATH"] if e.get("PYTHONPATH") else "")
    e["PYTHONUNBUFFERED"] = "1"
    e.setdefault("MPLBACKEND", "Agg")
    return e


_SCRATCH: dict[Path, Path] = {}


@pytest.fixture
def scratch(block, tmp_path_factory) -> Path:
    """One directory per page, shared by its blocks in order: symlinks to the repository, packages left out."""
    if block.page not in _SCRATCH:
        d = tmp_path_factory.mktemp(block.page.stem)
        for entry in ROOT.iterdir():
            if entry.name.startswith(".") or entry.name in PACKAGES or entry.suffix == ".egg-info":
                continue
            (d / entry.name).symlink_to(entry, target_is_directory=entry.is_dir())
        _SCRATCH[block.page] = d
    return _SCRATCH[block.page]


def run(argv_or_cmd, cwd: Path, timeout: float, stdin: str | None = None) -> None:
    shell = isinstance(argv_or_cmd, str)
    try:
        p = subprocess.run(["bash", "-c", argv_or_cmd] if shell else argv_or_cmd, cwd=cwd, env=env(), input=stdin,
                           capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        pytest.fail(f"timed out after {timeout:g} s: {argv_or_cmd}")
    assert p.returncode == 0, f"exit {p.returncode}: {argv_or_cmd}\n--- stdout\n{p.stdout[-3000:]}\n" \
                              f"--- stderr\n{p.stderr[-3000:]}"


def serve(cmd: str, cwd: Path, timeout: float, ready: str) -> None:
    words = bare(cmd)
    if words[:3] == ["python", "-m", "app"] and "--port" not in words and not any(
            w.startswith("--port=") for w in words):
        words.append("--port=0")
    proc = subprocess.Popen(words, cwd=cwd, env=env(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines: queue.Queue = queue.Queue()
    threading.Thread(target=lambda: [lines.put(ln) for ln in proc.stdout], daemon=True).start()
    log, ok = [], False
    deadline = time.monotonic() + timeout
    try:
        while not ok and time.monotonic() < deadline and proc.poll() is None:
            try:
                ln = lines.get(timeout=0.5)
            except queue.Empty:
                continue
            log.append(ln)
            ok = re.search(ready, ln) is not None
    finally:
        proc.send_signal(signal.SIGINT)  # the app's own exit path (KeyboardInterrupt -> app.close())
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    assert ok, f"{cmd!r} did not print {ready!r} within {timeout:g} s (exit {proc.returncode}):\n" + "".join(log)


def install_check(words: list[str], timeout: float) -> None:
    """pip install -> extras exist, then --dry-run --no-deps; apt-get install -> apt-get -s."""
    if words[0] == "sudo":
        words = words[1:]
    if words[0] == "apt-get":
        run(["apt-get", *words[1:2], "-s", *words[2:]], ROOT, timeout)
        return
    args = words[words.index("install") + 1:]
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"].get("optional-dependencies", {})
    for a in args:
        if m := re.fullmatch(r"\.\[([\w,\s-]+)\]", a):
            missing = {x.strip() for x in m.group(1).split(",")} - set(extras)
            assert not missing, f"pyproject.toml has no extra {missing}"
    key = tuple(re.sub(r"\[.*\]$", "", a) for a in args)  # extras checked above; --no-deps ignores them
    if key not in _DRY_RUNS:
        run([sys.executable, "-m", "pip", "install", "--dry-run", "--no-deps", *args], ROOT, timeout)
        _DRY_RUNS.add(key)


_DRY_RUNS: set[tuple[str, ...]] = set()  # pip's metadata build is ~10 s: once per target


def is_install(words: list[str]) -> bool:
    w = words[1:] if words[:1] == ["sudo"] else words
    return (w[:2] == ["pip", "install"] or w[:4] == ["python", "-m", "pip", "install"]
            or w[:2] == ["pip3", "install"] or w[:1] == ["apt-get"] or w[:1] == ["apt"])


def run_command(cmd: str, block: Block, cwd: Path) -> None:
    words = bare(cmd)
    timeout = float(block.opt("timeout", TIMEOUT))
    if not words:
        return
    if is_install(words):
        install_check(words, max(timeout, 120.0))
    elif "server" in dict(block.options) or (words[:3] == ["python", "-m", "app"] and words[3:4] != ["record"]):
        serve(cmd, cwd, float(block.opt("timeout", SERVER_TIMEOUT)), block.opt("ready", READY))
    elif words[:3] == ["python", "-m", "pytest"]:
        run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider", *words[3:]], ROOT,
            timeout)
    else:
        run(cmd, cwd, timeout)


def _param(b: Block):
    return pytest.param(b, id=b.id, marks=[pytest.mark.slow] if "slow" in dict(b.options) else [])


@pytest.mark.parametrize("block", [_param(b) for b in BLOCKS if b.lang in RUN + ("toml",)])
def test_block_runs(block, scratch):
    if block.lang == "python":
        run([sys.executable, "-"], scratch, float(block.opt("timeout", TIMEOUT)), stdin=block.code)
    elif block.lang == "toml":
        data = tomllib.loads(block.code)
        if "run" in data or "body" in data:
            import physics

            assert isinstance(physics.Scenario.from_dict(data), physics.Scenario)
    elif block.opt("run"):
        for cmd in commands(dataclasses.replace(block, code=block.opt("run").replace("{tmp}", str(scratch)))):
            run_command(cmd, block, scratch)
    else:
        cmds = commands(block)
        assert cmds, f"{block.id}: a shell block with no command"
        for cmd in cmds:
            run_command(cmd, block, scratch)


def test_a_stale_command_or_server_fails(tmp_path):
    """The runner is not a rubber stamp: a command that fails, and a server that exits before "ready", fail."""
    block = Block(tmp_path / "p.md", 1, "bash", "", ())
    with pytest.raises(AssertionError, match="exit 2"):
        run_command("python -m physics info assets/scenarios/no_such_file.toml", block, ROOT)
    with pytest.raises(AssertionError, match="did not print"):
        run_command("python -m app --scenario assets/scenarios/no_such_file.toml", block, ROOT)
    with pytest.raises(AssertionError, match="no extra"):
        install_check(["pip", "install", "-e", ".[no_such_extra]"], 10.0)


LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def test_local_links_and_images_exist():
    """A link or picture to a file of the repository (not http:, not a bare #anchor) points at a file that exists."""
    missing, checked = [], 0
    for page in PAGES:
        for target in LINK.findall(page.read_text(encoding="utf-8")):
            path = target.split("#", 1)[0]
            if not path or re.match(r"^[a-z]+:", path):
                continue
            checked += 1
            if not (page.parent / path).exists():
                missing.append(f"{page.relative_to(ROOT)}: {target}")
    assert not missing, "\n".join(missing)
    assert checked >= 10  # the pattern still finds the pages' pictures
