"""``python -m app``: serve the Quasirigid explorer (viser) and print its URL."""

from __future__ import annotations

import argparse
import sys
import time

import numpy as np

from .argv import numbers_as_values
from .serve.address import AddressError, listening_port, shown_host

LOOPBACK = ("127.0.0.1", "localhost", "::1")


def _whole(text: str) -> int | str:
    """--port's value: the whole number it spells, else the text (cut to 40 characters), which listening_port
    refuses as it refuses 70000, naming the range (argparse said only "invalid int value: '1e3'")."""
    try:
        return int(text)
    except ValueError:
        return text if len(text) <= 40 else text[:37] + "..."


def parse(argv: list[str] | None = None) -> argparse.Namespace:
    ap = numbers_as_values(argparse.ArgumentParser(
        prog="python -m app", description="Serve the Quasirigid explorer in the browser.",
        epilog="python -m app record [SCENARIO.toml] --seconds N --out demo.html writes a replay that any browser "
        "plays from the file (python -m app record --help)"))
    ap.add_argument("--host", default="127.0.0.1",
                    help="interface to bind (default 127.0.0.1; anything else exposes the explorer to the network)")
    ap.add_argument("--port", type=_whole, default=8080, help="port (default 8080; 0 = any free port)")
    ap.add_argument("--scenario", metavar="FILE.toml", help="open on this scenario instead of the default scene")
    ap.add_argument("--allow-origin", action="append", default=[], metavar="ORIGIN",
                    help="also accept browser connections from pages at ORIGIN (e.g. http://example.org); by "
                    "default only the explorer's own page may connect, so other sites cannot drive it")
    ap.add_argument("--mesh", metavar="FILE", help="draw the body as this closed mesh (STL, OBJ, PLY, GLB...); its "
                    "inertia, as a uniform solid of the scenario's mass M, replaces A, B, C")
    ap.add_argument("--class", dest="class_mode", action="store_true",
                    help="class mode: one run that the lecturer's tab drives and every student's tab follows; prints "
                    "the lecturer's link (it carries a key: keep it to yourself) and the students' link")
    return ap.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["record"]:  # `python -m app record ...`: write a replay file instead of serving (app.replay.cli)
        from .replay.cli import main as record_main

        return record_main(argv[1:])
    args = parse(argv)
    start = time.perf_counter()
    if not args.host.strip():
        print("error: --host '' names no interface; give one (default 127.0.0.1, loopback)", file=sys.stderr)
        return 2
    try:
        port = listening_port(args.host, args.port)
    except AddressError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if port != args.port:
        print(f"port {args.port} is in use (another explorer?): serving on {port}", flush=True)
    if args.host not in LOOPBACK:
        print(f"warning: --host {args.host} makes the explorer reachable from other machines; it has no "
              "authentication", file=sys.stderr, flush=True)
    print("Quasirigid explorer: starting the server...", flush=True)
    import viser  # the web server first, so a browser loads the page while the physics loads

    from .serve.guard import configure

    configure(args.host, tuple(args.allow_origin))  # same-origin browsers and this host's name only
    from .serve.page_scripts import install as install_page_scripts

    install_page_scripts()  # app/serve/page_scripts.py says what the page gets
    server = viser.ViserServer(host=args.host, port=port, label="Quasirigid")
    url = f"http://{shown_host(args.host)}:{server.get_port()}"
    print(f"serving {url}; loading the physics...", flush=True)
    import physics

    # compiles the integrator in a child process on a machine that has not yet; the tabs step interpreted meanwhile
    if physics.build_kernels().state == "pending":
        print("preparing the fast integrator in the background (once per machine); the scene runs meanwhile",
              flush=True)

    scenario = mesh = None
    try:
        if args.scenario:
            scenario = physics.Scenario.load(args.scenario)
        if args.mesh:
            from .engine.mesh import load_mesh, with_mesh

            base = scenario or physics.default_scenario()
            mesh = load_mesh(args.mesh, base.body.M)
            try:
                scenario = with_mesh(base, mesh)
                physics.LiveRun(scenario)  # the parts must fit the mesh's inertia
            except physics.ScenarioError as exc:
                if args.scenario:
                    raise
                from .engine.mesh import scaled_to  # the default scene's parts do not fit: scale the mesh to them

                scaled = scaled_to(mesh, base.body)
                scale = float(np.sqrt(np.sum(scaled.moments) / np.sum(mesh.moments)))
                mesh = scaled
                scenario = with_mesh(base, mesh)
                print(f"mesh {args.mesh}: as given, the default scene's parts do not fit it ({exc}); drawn "
                      f"{scale:.3g} times its size instead (give --scenario to keep its size)", flush=True)
            print(f"mesh {args.mesh}: principal moments A, B, C = {', '.join(f'{x:.6g}' for x in mesh.moments)} "
                  "kg m^2", flush=True)
        if scenario is not None:
            physics.LiveRun(scenario)
    except physics.ScenarioError as exc:
        server.stop()
        print(f"error: {exc}", file=sys.stderr)
        return 2
    from .serve.server import App, warm_up

    app = App(scenario=scenario, mesh=mesh, server=server, class_mode=args.class_mode)
    warm_up()
    print(f"Quasirigid explorer ready in {time.perf_counter() - start:.1f} s: {url}", flush=True)
    if app.classroom is not None:
        lecturer, students = app.classroom.links(url)
        print(f"lecturer: {lecturer}", flush=True)
        print(f"students: {students}", flush=True)
    try:
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        pass
    finally:
        app.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
