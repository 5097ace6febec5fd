"""One tab's 3-D scene: the body (its uniform shape or a mesh) inside its inertia ellipsoid, the internal
parts (the system's figure, app.scene.figure_view), the K, omega, e3 and braking-torque arrows with their labels, the
e3 trail and the polhode.
``draw_static`` redraws what changes only with the parameters; ``update`` moves what a frame moves.
"""

from __future__ import annotations

import numpy as np
import viser

from ..engine.engine import Engine
from ..engine.geometry import box_mesh, cylinder_mesh, trail_segments
from ..handles import set_if_changed
from . import camera
from .compare_view import CompareView
from .figure_view import FigureNodes
from .labels import label_groups
from .legend import COLORS, LegendView, parts_of
from .sphere_view import SphereView

ARROWS = ("K", "omega", "e3", "torque")  # the arrows' order (the first three in the arrows node), and in a merged label
SCENE_SIZE = 1.5  # scene units the body spans, whatever its size in metres


class Drawing:
    """The scene of one browser tab."""

    def __init__(self, client: viser.ClientHandle, engine: Engine):
        self.client = client
        self.engine = engine
        self.legend = LegendView(client.gui)  # what each arrow, line, trail and ball is (app.scene.legend)
        self._build_scene()
        camera.fit_when_known(client.camera)  # a narrow view moves the body clear of the legend

    def _build_scene(self) -> None:
        sc = self.client.scene
        camera.place(self.client.camera)
        self.root = f"/s{self.client.client_id}"
        # viser's default environment map costs a browser without a GPU (software WebGL) a 4-6 s stall
        # in about half the page loads, which pushed the first drawn frame past 5 s
        # (bench/explorer_startup.py); a hemisphere light gives the same soft fill at no such cost.
        sc.configure_environment_map(None)
        sc.add_light_hemisphere(f"{self.root}_fill", sky_color=(255, 255, 255), ground_color=(120, 120, 130),
                                intensity=1.5)
        sc.add_grid(f"{self.root}_grid", width=6.0, height=6.0, cell_size=0.25, position=(0.0, 0.0, -1.4))
        self.world = sc.add_frame(self.root, show_axes=False)
        self.handles: dict = {}
        self.parts = FigureNodes(sc, f"{self.root}/body")
        self.draw_static()
        self.sphere = SphereView(sc, self.root, self.engine)  # K in body axes beside the body (app.scene.sphere_view)
        self.compare = CompareView(sc, self.root, self.engine)  # compare mode's second body (app.scene.compare_view)

    def draw_static(self) -> None:
        """The parts that change only with the parameters: body shape, ellipsoid, the figure's nodes."""
        eng, sc, r = self.engine, self.client.scene, self.root
        old = [h for v in self.handles.values() for h in (v if isinstance(v, list) else [v])]
        for h in reversed(old):  # children before their parent frame
            if "/body/" in h.name and "body" in self.handles and h is not self.handles["body"]:
                continue  # removed with /body
            try:
                h.remove()
            except Exception:
                pass
        self.handles = {}
        self.parts.forget()  # under /body, removed with it above
        shape = eng.shape
        k = self.k = SCENE_SIZE / shape.extent  # scene units per metre: every body looks the same size
        s = SCENE_SIZE
        body = sc.add_frame(f"{r}/body", show_axes=True, axes_length=0.6 * s, axes_radius=0.01 * s)
        self.handles["body"] = body
        if eng.mesh is not None:
            vertices, faces = eng.mesh.vertices, eng.mesh.faces
        elif shape.kind == "box":
            vertices, faces = box_mesh(shape.dims)
        else:
            vertices, faces = cylinder_mesh(shape.radius, shape.height)
        self.handles["shape"] = sc.add_mesh_simple(f"{r}/body/shape", np.asarray(vertices) * k, faces,
                                                   color=COLORS["body"], opacity=0.45, flat_shading=False)
        self.handles["ellipsoid"] = sc.add_icosphere(f"{r}/body/ellipsoid", radius=1.0, color=COLORS["ellipsoid"],
                                                     scale=tuple(eng.ellipsoid() * k), opacity=0.15, subdivisions=3,
                                                     side="back")
        # back faces only: a translucent shell still writes depth, and three.js sorts translucent nodes by
        # their bounding spheres' centres, so a mesh whose centre is off the origin (the satellite's dish) was
        # drawn after the ellipsoid's near face and hidden behind it; the far face hides nothing inside
        self.parts.draw(eng.frame_figure(), k, s)
        look = dict(shaft_radius=0.012 * s, head_radius=0.035 * s, head_length=0.08 * s)
        colors = np.array([COLORS["K"], COLORS["omega"], COLORS["axis"]], dtype=np.uint8)
        self.handles["arrows"] = sc.add_arrows(f"{r}/arrows", np.zeros((3, 2, 3)), colors, **look)
        # the braking torque's arrow is a node of its own, hidden while there is none: an arrow of zero length
        # still draws its head, a magenta blob at the body's centre that the legend did not explain
        self.handles["torque"] = sc.add_arrows(f"{r}/torque", np.zeros((1, 2, 3)),
                                               np.array([COLORS["torque"]], dtype=np.uint8), visible=False, **look)
        self.handles["labels"] = [sc.add_label(f"{r}/lab_{n}", n, font_screen_scale=0.8, anchor="bottom-left")
                                  for n in ARROWS]  # slots: a merged label uses the first, the rest hide
        self.handles["trail"] = sc.add_line_segments(f"{r}/trail", np.zeros((1, 2, 3)), COLORS["trail"],
                                                     thickness=0.003 * s)
        self.handles["polhode"] = sc.add_line_segments(f"{r}/body/polhode", np.zeros((1, 2, 3)), COLORS["polhode"],
                                                       thickness=0.004 * s, visible=False)


    def update(self, fr, plots_now: bool) -> None:
        """Move what a frame moves (inside the session's ``client.atomic()``); redraw the static parts first
        when the engine says they changed."""
        eng = self.engine
        if eng.scene_changed:
            eng.scene_changed = False
            self.draw_static()
            eng.mark_drawn()
        h = self.handles
        h["body"].wxyz = fr.body_wxyz
        self.sphere.update(fr, plots_now)
        origin = np.zeros(3)
        k = self.k
        vecs = [k * v for v in (fr.K_vec, fr.omega_vec, fr.axis_vec)]
        h["arrows"].points = np.array([[origin, v] for v in vecs])
        vecs.append(k * fr.torque_vec if fr.torque_vec is not None else origin)
        if fr.torque_vec is not None:
            h["torque"].points = np.array([[origin, vecs[-1]]])
        set_if_changed(h["torque"], "visible", fr.torque_vec is not None)
        self.compare.update(k, SCENE_SIZE, plots_now)
        if plots_now:  # labels and trails change slowly: at the plots' rate, not every frame
            groups = label_groups(dict(zip(ARROWS, vecs, strict=True)), SCENE_SIZE)  # "K, omega, e3" when aligned
            for i, lab in enumerate(h["labels"]):
                if i < len(groups):
                    set_if_changed(lab, "text", groups[i][0])
                    lab.position = tuple(groups[i][1])
                set_if_changed(lab, "visible", i < len(groups))
            self.legend.show(parts_of(eng.scenario, view=eng.view, polhode=fr.polhode is not None,
                                      mesh=eng.mesh.name if eng.mesh is not None else None, figure=fr.figure,
                                      braking=fr.torque_vec is not None, sphere=eng.show_sphere,
                                      second=eng.compare.diff.label() if eng.compare is not None else None))
        self.parts.move(fr.figure, k, SCENE_SIZE)
        if plots_now and fr.trail is not None and len(fr.trail):
            h["trail"].points = trail_segments(k * fr.trail)
        set_if_changed(h["polhode"], "visible", fr.polhode is not None)
        if plots_now and fr.polhode is not None and len(fr.polhode):
            h["polhode"].points = trail_segments(k * fr.polhode)
