#!/usr/bin/env python3
"""Render a penumbra TOML scene with LuxCore (pyluxcore 2.11) for an equal-time comparison.

    python3 docs/luxcore/scene.py SECONDS OUT.exr --scene FILE.toml [--res WxH]
        [--engine BIDIRCPU|PATHCPU] [--threads 2] [--sampler SOBOL|RANDOM]
        [--eye-depth N] [--light-depth N] [--sphere-segments N] [--prop "k = v"]...

Maps the subset of the format used by scenes/cbox-mitsuba.toml and scenes/gap-room.toml:
shapes `mesh`, `quad` and `sphere` (tessellated), materials `diffuse` and `dielectric`,
one-sided `emission`, the perspective camera, `max_depth` and the box/gaussian filter.
Anything else stops with a message. Writes the film's linear "RGB" output (radiance, no
image pipeline) as a 32-bit float RGB OpenEXR with row 0 at the top, and prints the
samples per pixel reached and the elapsed time. See README.md beside this file.
"""
import argparse
import contextlib
import io
import math
import os
import sys
import time
import tomllib
from pathlib import Path

# numpy and OpenEXR must be imported BEFORE pyluxcore: the pyluxcore wheel preloads
# TBB's malloc proxy, and numpy imported after it aborts with "free(): invalid pointer".
import numpy as np
import OpenEXR

with contextlib.redirect_stdout(io.StringIO()):  # silence its "Checking dynamic libs"
    import pyluxcore


def rgb(v):
    """A penumbra colour (number = grey, or [r, g, b]) as three floats."""
    if isinstance(v, (int, float)):
        return [float(v)] * 3
    if isinstance(v, list) and len(v) == 3 and all(isinstance(x, (int, float)) for x in v):
        return [float(x) for x in v]
    sys.exit(f"colour {v!r}: only constant colours are mapped (no textures)")


def quad_mesh(s):
    """corner + a*edge1 + b*edge2 as two counter-clockwise triangles: the geometric
    normal (p1 - p0) x (p2 - p0) = edge1 x edge2, penumbra's front side."""
    c = np.array(s.get("corner", [-1, -1, 0]), float)
    e1 = np.array(s.get("edge1", [2, 0, 0]), float)
    e2 = np.array(s.get("edge2", [0, 2, 0]), float)
    verts = [c, c + e1, c + e1 + e2, c + e2]
    return verts, [(0, 1, 2), (0, 2, 3)]


def sphere_mesh(s, segments):
    """A UV sphere of `segments` x `segments/2` quads (flat triangles, no shading normals),
    every triangle wound so that its geometric normal points outwards like penumbra's."""
    ctr = np.array(s.get("center", [0, 0, 0]), float)
    r = float(s.get("radius", 1.0))
    nu, nv = segments, max(2, segments // 2)
    th = np.linspace(0.0, math.pi, nv + 1)[:, None]
    ph = np.linspace(0.0, 2 * math.pi, nu + 1)[None, :]
    grid = np.stack([np.sin(th) * np.cos(ph), np.cos(th) * np.ones_like(ph),
                     np.sin(th) * np.sin(ph)], -1)
    grid[:, -1] = grid[:, 0]                            # close the seam exactly
    pts = grid.reshape(-1, 3) * r + ctr
    i, j = np.meshgrid(np.arange(nv), np.arange(nu), indexing="ij")
    a, b = i * (nu + 1) + j, (i + 1) * (nu + 1) + j     # (i, j) and (i + 1, j)
    tris = np.concatenate([np.stack([a, b, b + 1], -1).reshape(-1, 3),
                           np.stack([a, b + 1, a + 1], -1).reshape(-1, 3)])
    p0, p1, p2 = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    n = np.cross(p1 - p0, p2 - p0)
    keep = np.linalg.norm(n, axis=1) > 1e-12 * r * r    # drop the poles' degenerate halves
    inward = np.einsum("ij,ij->i", n, (p0 + p1 + p2) / 3 - ctr) < 0
    tris[inward] = tris[inward][:, ::-1]
    tris = [tuple(t) for t in tris[keep]]
    return list(pts), tris


def camera_props(cam, w, h):
    """LuxCore's perspective `fieldofview` spans the default screen window's unit
    half-extent, i.e. the SMALLER image axis ([-w/h, w/h] x [-1, 1] for a wide image).
    penumbra's `fov` spans `fov_axis` (default "y"), so it is converted to the smaller
    axis: tan(f_lux / 2) = tan(f / 2) / (half-extent of that axis)."""
    if cam.get("type", "perspective") != "perspective" or cam.get("aperture_radius", 0):
        sys.exit("only the pinhole perspective camera is mapped")
    ax, ay = (w / h, 1.0) if w >= h else (1.0, h / w)
    axis = cam.get("fov_axis", "y")
    ext = {"x": ax, "y": ay, "smaller": 1.0, "larger": max(ax, ay)}[axis]
    fov = math.degrees(2 * math.atan(math.tan(math.radians(cam.get("fov", 45.0)) / 2) / ext))
    # LuxCore maps film y to raster y as `height - filmY - 1` (not `height - filmY`;
    # camera.cpp GenerateRay and GetSamplePosition alike), which moves the whole image
    # down by one pixel against Mitsuba/penumbra. Undo it by sliding the default screen
    # window down by one pixel.
    dy = 2.0 * ay / h
    return {"scene.camera.type": "perspective",
            "scene.camera.lookat.orig": [float(x) for x in cam.get("position", [0, 0, 5])],
            "scene.camera.lookat.target": [float(x) for x in cam.get("target", [0, 0, 0])],
            "scene.camera.up": [float(x) for x in cam.get("up", [0, 1, 0])],
            "scene.camera.fieldofview": fov,
            "scene.camera.screenwindow": [-ax, ax, -ay - dy, ay - dy]}


def material_props(m):
    """penumbra `diffuse` -> `matte` (Lambertian; both sides reflect, as penumbra's default
    two_sided = true); `dielectric` -> `glass` (exact Fresnel, smooth)."""
    t = m.get("type", "phong")
    if t == "diffuse":
        if not m.get("two_sided", True):
            sys.exit(f"material {m['name']}: one-sided diffuse is not mapped")
        return {"type": "matte", "kd": rgb(m.get("reflectance", 0.5))}
    if t == "dielectric":
        if any(k in m for k in ("roughness", "alpha_u", "alpha_v")):
            sys.exit(f"material {m['name']}: rough dielectrics are not mapped")
        # Inside = behind the front face (the sphere's outside, the quad's edge1 x edge2).
        return {"type": "glass", "kr": rgb(m.get("reflectance", 1.0)),
                "kt": rgb(m.get("transmittance", 1.0)),
                "interiorior": float(m.get("ior", 1.5)),
                "exteriorior": float(m.get("ior_outside", 1.0))}
    sys.exit(f"material {m['name']}: type {t!r} is not mapped")


def build_scene(cfg, w, h, segments):
    """Translate the TOML scene into a pyluxcore.Scene."""
    for key in ("light", "mesh", "environment"):
        if cfg.get(key):
            sys.exit(f"[{key}] is not mapped")
    if any(cfg.get("world", {}).get(k, 0) for k in ("background", "ambient")):
        sys.exit("[world] background/ambient are not mapped")
    scene = pyluxcore.Scene()
    p = pyluxcore.Properties()
    P = lambda k, v: p.Set(pyluxcore.Property(k, v))
    for k, v in camera_props(cfg.get("camera", {}), w, h).items():
        P(k, v)
    mats = {}
    for m in cfg.get("material", []):
        mats[m["name"]] = material_props(m)
        for k, v in mats[m["name"]].items():
            P(f"scene.materials.{m['name']}.{k}", v)

    for i, s in enumerate(cfg.get("shape", [])):
        if "transform" in s:
            sys.exit(f"shape {i}: `transform` is not mapped")
        if s["type"] == "mesh":
            if "file" in s or "normals" in s or "uvs" in s:
                sys.exit(f"shape {i}: only inline positions + indices are mapped")
            verts, tris = s["positions"], s["indices"]
        elif s["type"] == "quad":
            verts, tris = quad_mesh(s)
        elif s["type"] == "sphere":
            verts, tris = sphere_mesh(s, segments)
        else:
            sys.exit(f"shape {i}: type {s['type']!r} is not mapped")
        mesh = f"mesh{i}"
        # name, vertices, triangles, normals, uvs, colours, alphas (none: flat shading,
        # the geometric normal follows the counter-clockwise winding like penumbra's).
        scene.DefineMesh(mesh, [tuple(map(float, v)) for v in verts],
                         [tuple(map(int, t)) for t in tris], None, None, None, None)
        if "material" not in s:
            sys.exit(f"shape {i}: the default (phong) material is not mapped")
        mat = s["material"]
        if "emission" in s:
            # Emission lives on the LuxCore material, so an emitter gets its own copy of
            # its material. With emission.power = 0 and emission.efficiency = 0 LuxCore
            # does no power/lumen normalisation: the emitted radiance is simply
            # emission * emission.gain (W/m^2/sr, constant over the surface), which is
            # what penumbra's `emission` means. LuxCore area lights emit only on the
            # side of the geometric normal (emission.twosided defaults to false), as
            # penumbra's do with two_sided = false.
            if s.get("two_sided", False):
                sys.exit(f"shape {i}: two-sided emitters are not mapped")
            light = f"{mat}_emitter{i}"
            for k, v in mats[mat].items():
                P(f"scene.materials.{light}.{k}", v)
            for k, v in (("emission", rgb(s["emission"])), ("emission.gain", [1.0] * 3),
                         ("emission.power", 0.0), ("emission.efficiency", 0.0),
                         ("emission.normalizebycolor", False)):
                P(f"scene.materials.{light}.{k}", v)
            mat = light
        P(f"scene.objects.obj{i}.shape", mesh)
        P(f"scene.objects.obj{i}.material", mat)
    scene.Parse(p)
    return scene


def render_config(scene, w, h, max_depth, a, flt):
    """The render configuration: engine, depths, sampler, film, filter, halt time."""
    p = pyluxcore.Properties()
    P = lambda k, v: p.Set(pyluxcore.Property(k, v))
    P("renderengine.type", a.engine)
    P("native.threads.count", a.threads)
    P("sampler.type", a.sampler)
    # max_depth (Mitsuba's): at most max_depth path segments (camera ray included), i.e.
    # max_depth - 1 bounces.
    if a.engine == "PATHCPU":
        # PATHCPU's depth counts hit vertices: the camera ray's hit is depth 0; a hit at
        # depth d adds emission for d+1 segments and NEE for d+2, and NEE is skipped at
        # the last vertex (d = total - 1). So `total` = maximum number of segments.
        for k in ("total", "diffuse", "glossy", "specular"):
            P(f"path.pathdepth.{k}", max_depth)
    else:
        # BIDIRCPU: eye vertex depth t (1 = camera ray's hit) adds emission for t
        # segments and NEE for t+1; light vertex depth s (1 = first hit after leaving
        # the light) goes to the camera with s+1 segments; an eye/light connection has
        # t+s+1 segments. No cap on the total: with path.maxdepth = max_depth and
        # light.maxdepth = max_depth - 1 every strategy of every path up to max_depth
        # segments is present, but longer paths (up to 2*max_depth) still contribute
        # through the strategies that fit, with MIS weights that assume all do.
        eye, light = a.eye_depth or max_depth, a.light_depth or max_depth - 1
        P("path.maxdepth", eye)
        P("light.maxdepth", light)
        # Russian roulette OFF: with LuxCore's default (from depth 3, cap 0.5) BIDIRCPU
        # came out 12% / 5% / 3% (R/G/B) brighter than the reference on the Cornell box,
        # and within 1% with it off (see README.md). RR never fires at depth >= this.
        P("path.russianroulette.depth", max(eye, light) + 1)
    # PATHCPU keeps LuxCore's default Russian roulette (depth 3, cap 0.5): it matches.
    # Reconstruction filter (penumbra's default: gaussian, radius 1.5, sigma 0.5).
    # LuxCore's GAUSSIAN is exp(-alpha x^2) - exp(-alpha r^2), separable, with `width`
    # the radius in pixels; alpha = 1 / (2 sigma^2).
    kind = flt.get("type", "gaussian")
    if kind == "gaussian":
        sigma = float(flt.get("sigma", 0.5))
        P("film.filter.type", "GAUSSIAN")
        P("film.filter.width", float(flt.get("radius", 1.5)))
        P("film.filter.gaussian.alpha", 1.0 / (2.0 * sigma * sigma))
    elif kind == "box":
        P("film.filter.type", "BOX")
        P("film.filter.width", float(flt.get("radius", 0.5)))
    else:
        sys.exit(f"filter {kind!r} is not mapped")
    P("film.width", w)
    P("film.height", h)
    # The "RGB" film output is linear radiance (sum of radiance groups, normalised by
    # the filter weights); the image pipeline (tone mapping) does not touch it.
    P("film.imagepipelines.0.0.type", "TONEMAP_LINEAR")
    P("film.imagepipelines.0.0.scale", 1.0)
    P("film.outputs.0.type", "RGB")
    P("film.outputs.0.filename", "unused.exr")
    P("batch.halttime", a.seconds)
    for extra in a.prop:                  # --prop "key = value" overrides anything above
        p.Set(pyluxcore.Properties().SetFromString(extra))
    return pyluxcore.RenderConfig(p, scene)


def write_exr(path, img):
    channels = {c: np.ascontiguousarray(img[:, :, i], dtype=np.float32)
                for i, c in enumerate("RGB")}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, channels) as f:
        f.write(str(path))


def common_args(ap):
    """The arguments scene.py and pbrt.py share (after `seconds`, `out`, `--scene`, `--res`)."""
    ap.add_argument("--engine", default="BIDIRCPU", choices=["BIDIRCPU", "PATHCPU"])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--sampler", default="SOBOL", choices=["SOBOL", "RANDOM"])
    ap.add_argument("--eye-depth", type=int, help="BIDIRCPU path.maxdepth override")
    ap.add_argument("--light-depth", type=int, help="BIDIRCPU light.maxdepth override")
    ap.add_argument("--prop", action="append", default=[], metavar='"KEY = VALUE"',
                    help="extra LuxCore render-config property (repeatable)")
    ap.add_argument("--verbose", action="store_true", help="show LuxCore's log")


def main(default_scene=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("seconds", type=float, help="wall-clock render budget (batch.halttime)")
    ap.add_argument("out", help="output OpenEXR (linear RGB float)")
    ap.add_argument("--scene", default=default_scene, required=default_scene is None)
    ap.add_argument("--res", help="WxH, overrides [render] width/height like penumbra's")
    ap.add_argument("--sphere-segments", type=int, default=256,
                    help="sphere tessellation: N around, N/2 from pole to pole")
    common_args(ap)
    a = ap.parse_args()

    pyluxcore.Init((lambda msg: print(msg, file=sys.stderr)) if a.verbose else (lambda msg: None))
    cfg = tomllib.loads(Path(a.scene).read_text())
    r = cfg.get("render", {})
    w, h = r.get("width", 640), r.get("height", 480)
    if a.res:
        w, h = map(int, a.res.lower().split("x"))
    scene = build_scene(cfg, w, h, a.sphere_segments)
    config = render_config(scene, w, h, r.get("max_depth", 5), a, r.get("filter", {}))

    render_and_exit(config, w, h, a)


def render_and_exit(config, w, h, a, mirror=False):
    """Renders `config` until its halt time, writes the image to a.out (row 0 at the
    top; flipped left-right when `mirror`), prints spp, time and mean, and leaves."""
    session = pyluxcore.RenderSession(config)
    t0 = time.monotonic()
    session.Start()
    while not session.HasDone():          # batch.halttime stops the engine
        time.sleep(0.05)
        session.UpdateStats()
    elapsed = time.monotonic() - t0
    session.Stop()

    stats = session.GetStats()
    passes = stats.Get("stats.renderengine.pass").GetInt()
    img = np.zeros((h, w, 3), dtype=np.float32)
    session.GetFilm().GetOutputFloat(pyluxcore.FilmOutputType.RGB, img)
    img = img[::-1]                       # LuxCore's buffer has row 0 at the bottom
    if mirror:
        img = img[:, ::-1]
    write_exr(a.out, img)
    sps = stats.Get("stats.renderengine.total.samplesec").GetFloat()
    print(f"engine {a.engine} sampler {a.sampler} threads {a.threads} {w}x{h}: "
          f"{passes} spp in {elapsed:.2f} s ({sps / 1e6:.2f} M samples/s), "
          f"mean RGB {img.reshape(-1, 3).mean(0).round(5).tolist()} -> {a.out}")
    # pyluxcore 2.11 segfaults while the interpreter tears its objects down; all work
    # is done and written, so leave without running the finalisers.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


if __name__ == "__main__":
    main()
