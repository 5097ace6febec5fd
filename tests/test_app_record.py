"""The replay recorder without a browser (issue 16, point 3): ``python -m app record``'s arguments and refusals,
what a replay page carries (the scene's messages, the plots as a PNG, the title and the scenario, no URL a
browser would fetch), and ``physics.Trajectory.plot``. tests/test_app_browser_replay.py plays one in chromium."""

from __future__ import annotations

import base64
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import physics
from app.__main__ import main as app_main
from app.replay.export import file_name, replay_seconds
from app.replay.page import external_refs
from app.replay.record import MAX_SECONDS, REPLAY_FPS, record

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_TOML = ROOT / "physics" / "data" / "default.toml"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
SIM_TOL = 1e-9  # s: simulated time is warp * frames / fps, summed in floating point


def _refused(argv, capsys, *words):
    """``python -m app record ARGV`` exits 2 with one line on stderr that names the parameter: no traceback."""
    rc = app_main(["record", *argv])
    err = capsys.readouterr().err.strip()
    assert rc == 2, err
    assert len(err.splitlines()) == 1 and err.startswith("error: ") and "Traceback" not in err, err
    for word in words:
        assert word in err, err
    return err


@pytest.mark.parametrize("seconds", ["0", "-1", str(MAX_SECONDS + 1), "1e9", "nan", "inf", "abc", "5e-324", "0.0333",
                                     "-1e308"])
def test_seconds_outside_its_range_is_refused_naming_it(seconds, capsys, tmp_path):
    # 5e-324 s and anything short of one frame wrote a replay of 0 frames; -1e308 was argparse's "expected one
    # argument" until written --seconds=-1e308
    _refused([f"--seconds={seconds}", "--out", str(tmp_path / "x.html")], capsys, "--seconds", repr(seconds),
             f"1/{REPLAY_FPS:g} s (one frame) to {MAX_SECONDS:g} s")
    assert not (tmp_path / "x.html").exists()


@pytest.mark.parametrize("value", ["-1e308", "-5e-324", "-inf", "-NaN", "-1", "-.5"])
def test_a_negative_value_after_a_space_reaches_its_option_s_check(value, capsys, tmp_path):
    """``--seconds -1e308`` (a space, not "="): argparse read the value as an option of its own and said only
    "expected one argument" (app/argv.py). The explorer's own --port is read the same way."""
    _refused(["--seconds", value, "--out", str(tmp_path / "x.html")], capsys, "--seconds", repr(value),
             f"1/{REPLAY_FPS:g} s (one frame) to {MAX_SECONDS:g} s")
    _refused(["--seconds", "1", "--warp", value, "--out", str(tmp_path / "x.html")], capsys, "--warp", repr(value),
             "10000")
    try:  # argparse's own refusal (an int that is none) exits; the port's range check returns
        rc = app_main(["--port", value])
    except SystemExit as exc:
        rc = exc.code
    err = capsys.readouterr().err
    assert rc == 2, err
    assert "--port" in err and value in err and "expected one argument" not in err, err


def test_a_missing_or_bad_scenario_file_is_refused_naming_it(capsys, tmp_path):
    _refused([str(tmp_path / "nope.toml"), "--seconds", "1", "--out", str(tmp_path / "x.html")], capsys,
             "scenario", "nope.toml", "cannot be read")
    bad = tmp_path / "bad.toml"
    bad.write_text("[body\nA = 1\n")
    _refused([str(bad), "--seconds", "1", "--out", str(tmp_path / "x.html")], capsys, "scenario", "TOML")
    bad.write_text("[body]\nA = -1.0\nC = 1.4\nM = 1.0\n")
    _refused([str(bad), "--seconds", "1", "--out", str(tmp_path / "x.html")], capsys, "A")
    assert not (tmp_path / "x.html").exists()


def test_a_bad_out_or_warp_or_option_is_refused_naming_it(capsys, tmp_path):
    _refused(["--seconds", "1", "--out", str(tmp_path)], capsys, "--out", "directory")
    _refused(["--seconds", "1", "--out", ""], capsys, "--out ''", "names no file")  # was "'' is a directory"
    _refused(["--seconds", "1", "--out", str(tmp_path / "no" / "x.html")], capsys, "--out", "does not exist")
    _refused(["--seconds", "1", "--warp", "1e9", "--out", str(tmp_path / "x.html")], capsys, "--warp", "10000")
    _refused(["--seconds", "1", "--warp", "fast", "--out", str(tmp_path / "x.html")], capsys, "--warp")
    _refused(["--frames", "3"], capsys, "--frames")


def test_record_writes_one_self_contained_page_of_the_scenario(capsys, tmp_path):
    out = tmp_path / "demo.html"
    assert app_main(["record", str(DEFAULT_TOML), "--seconds", "1", "--warp", "2", "--out", str(out)]) == 0
    said = capsys.readouterr().out
    html = out.read_text(encoding="utf-8")
    assert f"({len(html.encode())} bytes)" in said and f"{int(REPLAY_FPS)} frames" in said, said
    assert external_refs(html) == []
    assert "window.__VISER_EMBED_DATA__=" in html  # viser's player, with the recording inline
    assert "<title>Quasirigid replay: default.toml: Quasirigid&#x27;s default scene" in html
    assert "1 s played at 2x: t = 0 to 2 s simulated" in html
    toml = re.search(r"<pre class='scenario'>(.*?)</pre>", html, re.S).group(1)
    assert "theta0 = 0.8" in toml and "[mass]" in toml  # the file itself, comments and all
    png = base64.b64decode(re.search(r"data:image/png;base64,([A-Za-z0-9+/=]+)", html).group(1))
    assert png.startswith(PNG_MAGIC)


def test_a_replay_is_warp_times_seconds_of_the_run_at_a_fixed_frame_rate():
    sc = physics.default_scenario()
    rep = record(sc, 2.0, title="two seconds", warp=3.0)
    assert rep.frames == int(2.0 * REPLAY_FPS)
    assert abs(rep.simulated - 6.0) < SIM_TOL  # exactly warp * played, however busy the machine was
    # every frame's pose change was kept with its time: the recording grows with the frames played
    longer = record(sc, 4.0, title="four seconds", warp=3.0)
    assert longer.size > rep.size
    assert abs(longer.simulated - 12.0) < SIM_TOL


def test_a_title_cannot_inject_markup_into_the_page():
    rep = record(None, 0.2, title="<script>alert(1)</script>", toml_text="# <b>x</b>\n")
    assert "<script>alert(1)</script>" not in rep.html and "&lt;script&gt;alert(1)&lt;/script&gt;" in rep.html
    assert "# &lt;b&gt;x&lt;/b&gt;" in rep.html


def test_external_refs_finds_what_a_browser_would_fetch():
    page = '<svg xmlns="http://www.w3.org/2000/svg"></svg><img src="https://example.org/a.png">'
    assert external_refs(page) == ["https://example.org/a.png"]


def test_the_export_button_records_as_long_as_the_tab_has_played_within_bounds():
    from app.engine.engine import Engine

    eng = Engine()
    eng.warp = 2.0
    eng._advance(30.0)
    assert replay_seconds(eng) == pytest.approx(eng.run.t / 2.0)
    eng._advance(200.0)
    assert replay_seconds(eng) == 60.0
    assert file_name("Default: oblate body settling (1 min)") == \
        "quasirigid-replay-default-oblate-body-settling-1-min.html"
    assert file_name("<>") == "quasirigid-replay.html"


def test_trajectory_plot_draws_theta_K_and_E_on_one_time_axis():
    tr = physics.simulate(physics.default_scenario())
    fig = tr.plot(title="default")
    axes = fig.get_axes()
    assert len(axes) == 3
    assert axes[0].get_shared_x_axes().joined(axes[0], axes[2])
    for ax, series in zip(axes, (tr.theta, tr.K, tr.E), strict=True):
        x, y = ax.get_lines()[0].get_data()
        np.testing.assert_array_equal(x, tr.t)
        np.testing.assert_array_equal(y, series)
    lo, hi = axes[1].get_ylim()  # |K| is conserved: drawn flat, with room around it, not as noise magnified
    assert hi - lo > 0.05 * tr.K.max()


def test_import_physics_does_not_import_matplotlib():
    code = "import sys, physics; print('matplotlib' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.stdout.strip() == "False", done.stderr


def test_the_export_replays_the_tabs_run_with_its_changes_at_their_times():
    """A tab that changed m at t = 1 s: the replay's run goes through the same change at the same t (within one
    frame), so it ends where the tab's run is, not where a run of the present scene from t = 0 would be."""
    from app.engine.engine import Engine
    from app.replay.record import REPLAY_FPS, copy_of_tab, record

    tab = Engine()
    for _ in range(60):
        tab._advance(1 / 60)
    tab.request_value("mass.m", 0.1)
    tab.tick(0.0)
    assert len(tab.retunes) == 1 and abs(tab.retunes[0][0] - tab.run.t) < 1e-12
    for _ in range(60):
        tab._advance(1 / 60)
    copy = copy_of_tab(tab)
    assert copy.scenario.mass.m == 0.2  # the scene the run began with
    replay = record(None, 2.0, title="t", engine=copy, changes=tab.retunes)
    assert copy.scenario.mass.m == 0.1 and replay.frames == 2 * REPLAY_FPS
    plain = copy_of_tab(tab)
    record(None, 2.0, title="t", engine=plain)  # the same scene from t = 0 with no changes made
    theta_tab, theta_copy, theta_plain = (float(e.run.last.theta[0]) for e in (tab, copy, plain))
    assert abs(theta_copy - theta_tab) < 0.2 * abs(theta_plain - theta_tab)
