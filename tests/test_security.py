"""Security and safe defaults (issue 7): loopback by default, a warning for anything else; nothing a
browser sends reaches a server path; uploads through the parser with a size cap; meshes from the command
line only, validated; no eval or pickle; dependencies bounded by versions the tests ran against."""

from __future__ import annotations

import builtins
import inspect
import io
import re
import tomllib
from importlib import metadata
from pathlib import Path

import numpy as np
import pytest
from packaging.requirements import Requirement

import physics
from app import __main__ as app_main
from app.engine.upload import MAX_UPLOAD_BYTES, display_name, parse_upload

ROOT = Path(__file__).resolve().parent.parent
SOURCES = [p for d in ("physics", "app", "bench") for p in (ROOT / d).rglob("*.py")]
GOOD = (ROOT / "physics" / "data" / "default.toml").read_bytes()


# ---- binding ----------------------------------------------------------------------------------------------
def test_loopback_is_the_default():
    from app.serve.server import App

    assert app_main.parse([]).host == "127.0.0.1"
    assert inspect.signature(App).parameters["host"].default == "127.0.0.1"


class _FakeServer:
    """Stands in for viser.ViserServer: records where it was asked to bind, serves nothing."""

    def __init__(self, host="0.0.0.0", port=8080, **_kwargs):
        self.host, self.port = host, port
        _FakeServer.made = self

    def get_port(self):
        return 1234

    def stop(self):
        pass


class _FakeApp:
    classroom = None  # not started with --class

    def __init__(self, *args, **kwargs):
        pass

    def close(self):
        pass


def _serve(monkeypatch, capsys, argv, code=0):
    """app.__main__.main with the web server faked and the wait interrupted at once."""
    import viser

    import app.serve.server

    monkeypatch.setattr(viser, "ViserServer", _FakeServer)
    # the hosts below need not be this machine's: whether they can be bound is tests/test_app_address.py's
    monkeypatch.setattr(app_main, "listening_port", lambda host, port, dashes="--": port)
    monkeypatch.setattr(app.serve.server, "App", _FakeApp)
    monkeypatch.setattr(app.serve.server, "warm_up", lambda: None)

    def interrupt(_seconds):
        raise KeyboardInterrupt

    monkeypatch.setattr(app_main.time, "sleep", interrupt)
    assert app_main.main(argv) == code
    return capsys.readouterr()


@pytest.mark.parametrize("host", ["0.0.0.0", "192.168.1.7", "::"])
def test_another_host_binds_there_with_a_warning(monkeypatch, capsys, host):
    out = _serve(monkeypatch, capsys, ["--host", host, "--port", "0"])
    assert _FakeServer.made.host == host
    assert f"warning: --host {host} makes the explorer reachable from other machines" in out.err
    assert "no authentication" in out.err


@pytest.mark.parametrize("argv, host", [([], "127.0.0.1"), (["--host", "localhost"], "localhost")])
def test_loopback_has_no_warning(monkeypatch, capsys, argv, host):
    out = _serve(monkeypatch, capsys, argv + ["--port", "0"])
    assert _FakeServer.made.host == host and "warning" not in out.err


# ---- no eval, exec or pickle ------------------------------------------------------------------------------
DANGEROUS = re.compile(r"\b(eval|exec)\s*\(|\bpickle\b|\bmarshal\b|\bshelve\b|yaml\.load\b|shell\s*=\s*True|"
                       r"allow_pickle\s*=\s*True|np\.load\s*\(|__import__\s*\(\s*[^\"']")


def test_no_eval_exec_or_pickle_in_the_sources():
    assert len(SOURCES) > 20
    hits = [f"{p.relative_to(ROOT)}:{i}: {line.strip()}" for p in SOURCES
            for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1)
            if DANGEROUS.search(line.split("#")[0])]
    assert hits == []


def test_the_scan_would_see_them():
    for line in ("x = eval(s)", "exec (code)", "import pickle", "np.load(f, allow_pickle=True)",
                 "subprocess.run(c, shell=True)", "yaml.load(s)"):
        assert DANGEROUS.search(line), line


# ---- uploads ----------------------------------------------------------------------------------------------
def test_an_upload_goes_through_the_parser():
    assert parse_upload("scenario.toml", GOOD) == physics.Scenario.from_toml(GOOD.decode())
    assert parse_upload("x.toml", b"\xef\xbb\xbf" + GOOD) == physics.default_scenario()  # a BOM is fine


@pytest.mark.parametrize("content, needle", [
    (GOOD + b"#" * MAX_UPLOAD_BYTES, f"must be at most {MAX_UPLOAD_BYTES} bytes"),
    (b"", "empty"),
    (b"\xff\xfe\x00[", "must be UTF-8 text"),
    (GOOD.replace(b"m = 0.2", b"m = -0.2"), "mass.m = -0.2: must be > 0"),
    (GOOD + b"\n[evil]\n", "evil = (table): unknown table"),
    (b"[body\n", "is not valid TOML"),
    ("text, not bytes", "must be the bytes of a file"),
])
def test_a_bad_upload_is_rejected_with_a_clear_message(content, needle):
    with pytest.raises(physics.ScenarioError) as info:
        parse_upload("up.toml", content)
    assert needle in str(info.value) and "\n" not in str(info.value)


def test_the_size_cap_is_checked_before_parsing(monkeypatch):
    def never(_text):
        raise AssertionError("parsed an oversized upload")

    monkeypatch.setattr(physics.Scenario, "from_toml", never)
    with pytest.raises(physics.ScenarioError, match="at most 100 bytes"):
        parse_upload("big.toml", b"x" * 101, max_bytes=100)


def test_an_upload_name_is_shown_never_opened():
    assert display_name("../../etc/passwd") == "passwd"
    assert display_name("C:\\Users\\x\\s.toml") == "s.toml"
    shown = display_name("<b>**x**</b>\n.toml")
    assert not set(shown) & set("<>*\n/\\`[]")
    assert display_name("") == "scenario.toml" and len(display_name("a" * 500)) == 80


def test_a_refused_uploads_keys_are_shown_as_text_under_the_button():
    from app.panel.panel import _upload_md
    from app.state import Engine

    eng = Engine()
    eng.request("upload", ("evil.toml", b"[mass]\n'<img src=x onerror=\"alert(1)\">' = 1\n'**bold**' = 2\n"))
    eng.tick(0.02)
    assert eng.upload_note[0] == "refused" and "<img" in eng.upload_note[1]  # physics names the key as it was
    shown = _upload_md(eng.upload_note)
    assert shown.startswith("<span style='color:#c00'>") and "unknown key" in shown
    assert "<img" not in shown and "&lt;img" in shown and "**bold**" not in shown  # escaped: shown, never rendered


class _Opened:
    """Records every file the process opens through open() / Path.open()."""

    def __init__(self, monkeypatch):
        self.paths: list[Path] = []
        real = builtins.open

        def spy(file, *args, **kwargs):
            if isinstance(file, (str, bytes, Path)):
                self.paths.append(Path(file if not isinstance(file, bytes) else file.decode(errors="replace")))
            return real(file, *args, **kwargs)

        monkeypatch.setattr(builtins, "open", spy)
        monkeypatch.setattr(io, "open", spy)

    def outside(self, *allowed: Path) -> list[Path]:
        return [p for p in self.paths if not any(p.resolve().is_relative_to(a) for a in allowed)]


EVIL_PATHS = ["/etc/passwd", "../../../../etc/passwd", str(ROOT / "pyproject.toml"), "/dev/zero", "~/.ssh/id_rsa"]


@pytest.mark.parametrize("action", ["preset", "system", "fidelity", "view", "overlay", "upload", "mesh"])
def test_nothing_a_browser_sends_opens_a_server_path(monkeypatch, action):
    """Every action that carries a string from the browser, given paths: the engine opens nothing outside
    the shipped assets, rejects what is not one of its choices, and keeps the previous valid scenario."""
    from app.state import Engine

    eng = Engine()
    eng.tick(0.02)
    before, t_before = eng.scenario, eng.run.t
    opened = _Opened(monkeypatch)
    for evil in EVIL_PATHS:
        value = (evil, GOOD.replace(b"[body]", b"[body]\nfile = 1")) if action == "upload" else evil
        eng.request(action, value)
        eng.tick(0.02)
        assert eng.scenario == before  # a rejected change leaves the previous valid scenario in place
        assert physics.Scenario.from_toml(eng.toml().decode()) == before  # and it can be exported
    assert opened.outside(ROOT / "assets", ROOT / "physics" / "data") == []
    assert eng.run.t >= t_before and np.all(np.isfinite(eng.run.y))
    if action in ("preset", "mesh"):
        assert eng.error  # said why
    if action == "upload":  # said why, beside the upload button rather than at the top of the panel
        assert eng.upload_note[0] == "refused" and "file" in eng.upload_note[1] and not eng.error


# ---- meshes: command line only, validated ------------------------------------------------------------------
def test_a_mesh_path_comes_only_from_the_command_line():
    """A browser picks a shipped mesh by name (app/engine/mesh.py asset_path); a file path is the command line's."""
    server = (ROOT / "app" / "serve" / "server.py").read_text()
    assert "load_mesh(" not in server
    callers = {p.relative_to(ROOT).as_posix() for p in SOURCES if "load_mesh(" in p.read_text() and p.name != "mesh.py"}
    assert callers <= {"app/__main__.py", "app/engine/actions.py", "bench/figures.py"}, callers
    if "app/engine/actions.py" in callers:  # the GUI's mesh choice: only through the assets folder's names
        state = (ROOT / "app" / "engine" / "actions.py").read_text()
        assert state.count("load_mesh(") == state.count("load_mesh(path") and "path = meshes.asset_path(name)" in state


@pytest.mark.parametrize("content", [b"", b"solid x\nfacet normal 0 0 1\n", b"\x00" * 300, b"v 1 2\nf 1 2 3\n",
                                     b"ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n"])
def test_a_malformed_mesh_file_gives_a_clear_error(tmp_path, content):
    from app.engine.mesh import load_mesh

    folder = tmp_path / ("a folder whose name is long " * 4).strip()  # a path past the 80 characters a value gets
    folder.mkdir()
    path = folder / "broken.stl"
    path.write_bytes(content)
    with pytest.raises(physics.ScenarioError) as info:
        load_mesh(path, 1.0)
    msg = str(info.value)
    assert msg.startswith("--mesh = ") and str(path) in msg and "\n" not in msg


def test_a_missing_mesh_through_the_command_line_exits_2(monkeypatch, capsys, tmp_path):
    err = _serve(monkeypatch, capsys, ["--mesh", str(tmp_path / "none.stl"), "--port", "0"], code=2).err
    assert err.startswith("error: --mesh = ") and err.count("\n") == 1


# ---- dependencies ----------------------------------------------------------------------------------------
def _requirements() -> list[Requirement]:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    reqs = list(project["dependencies"])
    for extra in project.get("optional-dependencies", {}).values():
        reqs += extra
    return [Requirement(r) for r in reqs]


def test_every_dependency_is_bounded_and_the_installed_version_satisfies_it():
    reqs = _requirements()
    assert {"numpy", "scipy", "numba", "viser"} <= {r.name for r in reqs}
    for r in reqs:
        ops = {s.operator for s in r.specifier}
        assert ops & {">=", ">", "==", "~="}, f"{r}: no lower bound"
        assert ops & {"<", "<=", "==", "~="}, f"{r}: no upper bound"
        installed = metadata.version(r.name)
        assert r.specifier.contains(installed, prereleases=True), f"{r.name} {installed} is outside {r.specifier}"
