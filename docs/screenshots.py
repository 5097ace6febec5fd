"""Screenshots for docs/guide.md: the explorer in headless Debian chromium (Playwright), one PNG per recipe.

    python docs/screenshots.py [--only NAME ...] [--out docs/img]

Starts app.serve.server.App in-process on a free port (as bench/explorer_rates.py does), opens one page, and for
each shot chooses a preset through the tab's engine (and shows the choice in the panel), lets the simulation
run for a few seconds and saves docs/img/guide_<name>.png (1280 x 800). Re-run it whenever the explorer's
panel or scene changes; a shot whose preset no longer exists fails loudly rather than being skipped.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run as a script from anywhere

from playwright.sync_api import sync_playwright  # noqa: E402

from app.engine import presets  # noqa: E402
from app.serve.server import App, warm_up  # noqa: E402

CHROMIUM = "/usr/bin/chromium"
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]
VIEWPORT = {"width": 1280, "height": 800}
CONNECT_TIMEOUT = 120_000  # ms: a cold numba cache compiles the kernels before the first session


@dataclass(frozen=True)
class Shot:
    """One screenshot: a preset, GUI values to show (handle name on the Session -> value) with the engine
    action each one requests, and how long to let it run first."""

    name: str
    preset: str
    seconds: float = 6.0
    settings: tuple[tuple[str, str, object], ...] = ()  # (session attribute, engine action, value)
    warp: float | None = None
    folders: tuple[str, ...] = field(default=())  # slider folders to open (titles in app/engine/controls.py FOLDERS)
    scroll_to: str = "Run"  # panel text brought to the top of the panel (default: the Run row, its top)
    file: str = ""  # the PNG's name in --out (default guide_<name>.png)
    size: tuple[int, int] | None = None  # the page's size for this shot (default VIEWPORT)
    wheel: int = 0  # px the panel is then scrolled with the mouse wheel (a chart's title cannot be scrolled to)


SHOTS = (
    Shot("readme", presets.DEFAULT, seconds=20.0, file="explorer.png", size=(1400, 900)),  # README's picture
    Shot("overview", presets.DEFAULT, seconds=10.0),
    Shot("sliders", presets.DEFAULT, seconds=3.0, scroll_to="Moving mass, medium, braking"),
    Shot("damper", "Large spinning body, pendulum damper detuned (half the nutation frequency)", seconds=8.0,
         folders=("Pendulum damper",),
         scroll_to="Model"),
    Shot("energy_sink_oblate", "Oblate body settling", seconds=10.0, warp=1000.0),
    Shot("energy_sink_prolate", "Explorer 1's flat spin", seconds=12.0, warp=150.0),
    Shot("overlay", presets.DEFAULT, seconds=14.0, settings=(("overlay", "overlay", "averaged"),)),
    Shot("braking", "Braking with a fluid cavity and a resisting medium", seconds=10.0),
    Shot("momentum_sphere", presets.DEFAULT, seconds=20.0, warp=3.0, wheel=640,
         file="momentum_sphere.png", size=(1400, 900)),
    Shot("momentum_sphere_flip", "Asymmetric body: intermediate-axis flip", seconds=15.0,
         wheel=640, file="momentum_sphere_flip.png", size=(1400, 900)),
    Shot("figure_preset", "Braking an oblate body with a mass, a cavity and a medium (|Gamma1| = 10, k* = 0.5; "
         "Zinkevich et al., Fig. 3, physical counterpart)",
         seconds=12.0, scroll_to="Model"),
)
MESH_SHOT = "mesh"
MESH_FILE = ROOT / "assets" / "meshes" / "satellite.stl"
MESH_SCENARIO = ROOT / "assets" / "scenarios" / "prolate_flat_spin.toml"  # its mass fits inside the satellite
PALETTE = 256  # colours: the PNGs are quantized to keep the repository small


def _session(app: App, page, timeout_ms: int = CONNECT_TIMEOUT):
    waited = 0
    while not app.sessions:
        if waited > timeout_ms:
            raise TimeoutError("no session connected")
        page.wait_for_timeout(200)
        waited += 200
    return next(iter(app.sessions.values()))


def _open(browser, app: App):
    page = browser.new_page(viewport=VIEWPORT)
    page.set_default_timeout(CONNECT_TIMEOUT)
    page.goto(f"http://127.0.0.1:{app.port}")
    page.wait_for_selector("canvas")
    session = _session(app, page)
    page.wait_for_timeout(3000)  # the scene fades in
    close = page.locator(".mantine-Notification-root button")  # "software WebGL" notice: not the explorer's
    for i in range(close.count()):
        close.nth(i).click()
    return page, session


def _scroll(page, text: str) -> None:
    exact = page.get_by_text(text, exact=True)
    target = exact if exact.count() else page.get_by_text(text)
    target.first.evaluate("e => e.scrollIntoView({block: 'start'})")
    page.wait_for_timeout(300)


def _save(page, path: Path) -> Path:
    page.screenshot(path=str(path))
    try:
        from PIL import Image

        Image.open(path).convert("RGB").quantize(colors=PALETTE, method=Image.Quantize.MEDIANCUT).save(
            path, optimize=True)
    except ImportError:  # Pillow comes with matplotlib; without it the PNG is just larger
        pass
    return path


def _open_folders(page, titles) -> None:
    for title in titles:
        page.get_by_text(title, exact=True).first.click()
        page.wait_for_timeout(300)


def take(session, page, shot: Shot, out: Path) -> Path:
    eng = session.engine
    if shot.preset not in presets.preset_names():
        raise KeyError(f"shot {shot.name!r}: no preset {shot.preset!r}")
    eng.request("preset", shot.preset)
    eng.request("play")
    session.panel.overlay.value = "none"  # a previous shot's overlay: each shot starts from a clean panel
    eng.request("overlay", "none")
    page.wait_for_timeout(1500)  # the preset loads and the panel follows
    for attr, action, value in shot.settings:
        getattr(session.panel, attr).value = value  # shows it in the panel (a server-side set is not a user's change)
        eng.request(action, value)
    if shot.warp is not None:
        eng.request("warp", shot.warp)
    if shot.size is not None:
        page.set_viewport_size({"width": shot.size[0], "height": shot.size[1]})
    _open_folders(page, shot.folders)
    page.wait_for_timeout(int(shot.seconds * 1000))
    _scroll(page, shot.scroll_to)
    if shot.wheel:
        page.mouse.move(page.viewport_size["width"] - 200, page.viewport_size["height"] // 2)  # over the panel
        page.mouse.wheel(0, shot.wheel)
        page.wait_for_timeout(500)
    path = _save(page, out / (shot.file or f"guide_{shot.name}.png"))
    if shot.size is not None:
        page.set_viewport_size(VIEWPORT)
    _open_folders(page, shot.folders)  # close them again for the next shot
    return path


def mesh_shot(browser, out: Path) -> Path:
    """`python -m app --scenario assets/scenarios/prolate_flat_spin.toml --mesh assets/meshes/satellite.stl`."""
    import physics
    from app.engine.mesh import load_mesh, with_mesh

    base = physics.Scenario.load(MESH_SCENARIO)
    mesh = load_mesh(MESH_FILE, base.body.M)
    app = App(port=0, scenario=with_mesh(base, mesh), mesh=mesh)
    try:
        page, session = _open(browser, app)
        session.engine.request("warp", 5.0)  # early in the run, while the satellite still stands up
        session.engine.request("reset")
        page.wait_for_timeout(6000)
        path = _save(page, out / f"guide_{MESH_SHOT}.png")
        page.close()
    finally:
        app.close()
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", nargs="*", help="shot names (default: all): " + ", ".join(
        [s.name for s in SHOTS] + [MESH_SHOT]))
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "img")
    args = ap.parse_args(argv)
    wanted = set(args.only or [s.name for s in SHOTS] + [MESH_SHOT])
    args.out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    warm_up()
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
        shots = [s for s in SHOTS if s.name in wanted]
        if shots:
            app = App(port=0)
            try:
                page, session = _open(browser, app)
                for shot in shots:
                    print(f"{shot.name}: {take(session, page, shot, args.out)}", flush=True)
                page.close()
            finally:
                app.close()
        if MESH_SHOT in wanted:
            print(f"{MESH_SHOT}: {mesh_shot(browser, args.out)}", flush=True)
        browser.close()
    print(f"done in {time.perf_counter() - start:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
