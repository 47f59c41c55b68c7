"""The add-on's viewport latency on the demo scene, in Blender with its window (run it through
bench/blender/run: Xvfb, Mesa's software OpenGL). Not a test: it prints figures.

Blender draws a RenderEngine's viewport (view_update / view_draw) only in a window: `blender -b`
has no 3D view to draw, so this runs under xvfb-run. The demo scene is built in Blender
(demo_scene.py); the largest area becomes a 3D view in the camera view, overlays off, and:

- *on*: Rendered shading turned on (the meshes exported, the scene loaded) to the first image
  view_draw drew;
- *camera edit*: the camera's fov changed (no export: the preview restarts), to the first image
  drawn of the restarted preview; each edit made after the last preview finished all its
  passes (*idle*) and, again, while the preview renders its 4-spp pass (*busy*: the running
  pass is cancelled first);
- *mesh edit*: the torus knot moved (the first move exports it alone, later ones place it by a
  transform), to the first image drawn;
- *vertex edit*: the box's vertices scaled (its geometry changed: the meshes exported again).

Times are time.monotonic() from just before the edit in this script to view_draw's first draw
of the new preview's image (bl.viewport_log's first_drawn), and where it went: the export, the
rendering thread's load + first pass (first_image - started)."""

import os
import statistics
import sys
import time

import addon_utils
import bpy

REPO, OUT = sys.argv[sys.argv.index("--") + 1:][:2]
REPS = int(os.environ.get("REPS", "10"))
POLL = float(os.environ.get("POLL", "0.002"))
# ADDON_DIR: another copy of the add-on's folder (e.g. an older one, to compare).
sys.path.insert(0, os.environ.get("ADDON_DIR") or os.path.join(REPO, "blender"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import demo_scene  # noqa: E402

state = {"phase": "start", "results": {}}
bl = None


def area():
    win = bpy.context.window_manager.windows[0]
    return max(win.screen.areas, key=lambda a: a.width * a.height)


def setup():
    global bl
    win = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=win, screen=win.screen):
        scene = demo_scene.build(REPO)
    addon_utils.enable("anamorph_blender", default_set=True, handle_error=None)
    from anamorph_blender import bl as bl_module

    bl = bl_module
    if bl._load_error:
        raise RuntimeError("the add-on could not load anamorph: " + bl._load_error)
    instrument()
    scene.render.engine = "ANAMORPH"
    scene.anamorph.integrator = "whitted"
    scene.anamorph.max_depth = 6
    a = area()
    a.type = "VIEW_3D"
    space = a.spaces.active
    space.overlay.show_overlays = False
    space.region_3d.view_perspective = "CAMERA"
    space.region_3d.view_camera_zoom = 0
    print("viewport area %d x %d" % (a.width, a.height), flush=True)


events = []  # (time, what) of the engine's calls, for the timeline of each edit


def instrument():
    """Wraps the engine's view_update, view_draw and the viewport's export to log their times."""
    eng = bl.AnamorphRenderEngine
    for name in ("view_update", "view_draw"):
        def wrap(fn, name=name):
            def call(self, context, depsgraph):
                t = time.monotonic()
                if name == "view_update" and os.environ.get("UPDATES"):
                    events.append((t, "updates " + ", ".join(
                        "%s(%s%s)" % (type(u.id).__name__, "g" if u.is_updated_geometry else "",
                                      "s" if u.is_updated_shading else "")
                        for u in depsgraph.updates)))
                fn(self, context, depsgraph)
                events.append((t, "%s %.1f ms" % (name, 1e3 * (time.monotonic() - t))))
            return call
        setattr(eng, name, wrap(getattr(eng, name)))
    export = bl._export_glb

    def timed_export(*a, **kw):
        t = time.monotonic()
        r = export(*a, **kw)
        events.append((t, "export %.1f ms" % (1e3 * (time.monotonic() - t))))
        return r
    bl._export_glb = timed_export
    stop = bl._Preview.stop

    def timed_stop(self):
        t = time.monotonic()
        stop(self)
        events.append((t, "stop %.1f ms" % (1e3 * (time.monotonic() - t))))
    bl._Preview.stop = timed_stop


def timeline(t0):
    if os.environ.get("TIMELINE"):
        print("   " + "; ".join("%.0f %s" % (1e3 * (t - t0), w) for t, w in events if t >= t0))


def latest():
    return bl.viewport_log[-1] if bl.viewport_log else None


def record(kind, t0, exports_before):
    """One edit's times [s] from t0: the engine's first view_update after it, the preview's
    restart, its first image rendered and drawn."""
    log = latest()
    update = min((t for t, w in events if t >= t0 and w.startswith("view_update")),
                 default=float("nan"))
    r = {"update": update - t0, "started": log["started"] - t0,
         "image": log["first_image"] - t0, "drawn": log["first_drawn"] - t0,
         "draw": draw_call(log["first_drawn"]),
         "exports": len(bl.viewport_exports) - exports_before,
         "reused": bool(log.get("reused"))}
    state["results"].setdefault(kind, []).append(r)
    print("%s: view_update %.0f, restart %.0f, image rendered %.0f, drawn %.0f ms (%d export; "
          "its view_draw %.1f ms)" % (kind, *(1e3 * r[k] for k in (
              "update", "started", "image", "drawn")), r["exports"], 1e3 * r["draw"]),
          flush=True)
    timeline(t0)


def draw_call(t):
    """How long the view_draw call that first drew an image (at time t) took [s]."""
    calls = [(s, w) for s, w in events if w.startswith("view_draw") and s <= t]
    return float(calls[-1][1].split()[1]) * 1e-3 if calls else float("nan")


def drawn_after(t0):
    log = latest()
    return log is not None and log["started"] > t0 and log.get("first_drawn") is not None


def settled(t0):
    log = latest()
    return drawn_after(t0) and log["passes"] == len(bl.VIEWPORT_PASSES)


# Each edit: (kind, function making it, whether to wait for the preview to finish first).
def edit_fov(i):
    cam = bpy.context.scene.camera.data
    cam.angle = 0.96 if i % 2 else 0.94


def edit_mesh(i):
    knot = bpy.data.objects["torus_knot"]
    knot.location.x = 0.05 if i % 2 else -0.05


def edit_vertices(i):
    """The cube's vertices scaled up and down (its geometry: exported again)."""
    mesh = bpy.data.objects["box"].data
    for v in mesh.vertices:
        v.co *= 1.02 if i % 2 else 1 / 1.02
    mesh.update()


PLAN = [("camera edit, idle", edit_fov, "idle")] * REPS + \
    [("camera edit, busy", edit_fov, "busy")] * REPS + \
    [("mesh edit, idle", edit_mesh, "idle")] * REPS + \
    [("vertex edit, idle", edit_vertices, "idle")] * REPS
if os.environ.get("CASES"):  # e.g. CASES="camera edit, idle;mesh edit, idle"
    PLAN = [p for p in PLAN if p[0] in os.environ["CASES"].split(";")]


_last_step = [0.0]


def step():
    now = time.monotonic()
    if os.environ.get("TIMELINE") and now - _last_step[0] > 0.012:
        events.append((_last_step[0], "main loop away %.0f ms" % (1e3 * (now - _last_step[0]))))
    _last_step[0] = now
    try:
        return _step()
    except Exception:  # a timer's exception would leave Blender running
        import traceback

        traceback.print_exc()
        os._exit(1)


def _step():
    s = state
    if s["phase"] == "start":  # an empty scene, which also closes the splash screen
        bpy.ops.wm.read_factory_settings(use_empty=True)
        s["phase"] = "setup"
        return 0.5
    if s["phase"] == "setup":
        setup()
        s["phase"] = "on"
        return 1.0
    if s["phase"] == "on":
        s.update(phase="wait", t0=time.monotonic(), kind="on", exports=0, i=0)
        area().spaces.active.shading.type = "RENDERED"
        return POLL
    if s["phase"] == "wait":
        if time.monotonic() - s["t0"] > 60:
            raise RuntimeError("no image within 60 s (log %s)" % bl.viewport_log[-2:])
        if not drawn_after(s["t0"]):
            return POLL
        record(s["kind"], s["t0"], s["exports"])
        s["phase"] = "next"
    if s["phase"] == "next":
        if s["i"] >= len(PLAN):
            return report()
        kind, fn, when = PLAN[s["i"]]
        log = latest()
        ready = settled(0) if when == "idle" else (log["passes"] == 3)
        if not ready:
            if time.monotonic() - log["started"] > 120:
                raise RuntimeError("the preview did not get there in 120 s (log %s)" % log)
            return POLL
        s.update(phase="wait", kind=kind, exports=len(bl.viewport_exports), t0=time.monotonic())
        fn(s["i"])
        s["i"] += 1
        return POLL
    return 0.05


def report():
    """Medians over the runs of each case [ms after the edit], and the first image drawn's
    90th percentile; `reused`: restarts that rendered a scene loaded before (a new view only)."""
    print("\n| case | runs | view_update | preview restarted | first image rendered | "
          "first image drawn: median, p90 (min-max) | image to view_draw | its view_draw | exports "
          "| reused |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for kind, rs in state["results"].items():
        med = {k: 1e3 * statistics.median(r[k] for r in rs)
               for k in ("update", "started", "image", "drawn", "draw")}
        med["wait"] = 1e3 * statistics.median(r["drawn"] - r["draw"] - r["image"] for r in rs)
        drawn = [1e3 * r["drawn"] for r in rs]
        p90 = statistics.quantiles(drawn, n=10)[-1] if len(drawn) > 1 else drawn[0]
        print("| %s | %d | %.0f ms | %.0f ms | %.0f ms | **%.0f ms**, %.0f ms (%.0f-%.0f) | "
              "%.0f ms | %.1f ms | %d | %d |" % (
                  kind, len(rs), med["update"], med["started"], med["image"], med["drawn"], p90,
                  min(drawn), max(drawn), med["wait"], med["draw"], max(r["exports"] for r in rs),
                  sum(r["reused"] for r in rs)))
    print("\nviewport passes %s; load average %s" % (
        bl.VIEWPORT_PASSES, open("/proc/loadavg").read().split()[:3]), flush=True)
    os._exit(0)


bpy.app.timers.register(step, first_interval=1.0, persistent=True)
