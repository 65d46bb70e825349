#!/usr/bin/env python3
"""Render penumbra's scenes/cbox-mitsuba.toml with LuxCore (pyluxcore 2.11) for an
equal-time comparison.

    python3 docs/luxcore/cbox.py SECONDS OUT.exr [--engine BIDIRCPU|PATHCPU] [--threads 2]
        [--sampler SOBOL|RANDOM] [--scene FILE.toml] [--eye-depth N] [--light-depth N]

Writes the film's linear "RGB" output (radiance, no image pipeline) as a 32-bit float
RGB OpenEXR with row 0 at the top, and prints the samples per pixel reached and the
elapsed time. See README.md beside this file for the mapping and its caveats.
"""
import argparse
import os
import sys
import time
import tomllib
from pathlib import Path

import contextlib
import io

# numpy and OpenEXR must be imported BEFORE pyluxcore: the pyluxcore wheel preloads
# TBB's malloc proxy, and numpy imported after it aborts with "free(): invalid pointer".
import numpy as np
import OpenEXR

with contextlib.redirect_stdout(io.StringIO()):  # silence its "Checking dynamic libs"
    import pyluxcore

DEFAULT_SCENE = Path(__file__).resolve().parents[2] / "scenes" / "cbox-mitsuba.toml"


def build_scene(cfg):
    """Translate the TOML scene into a pyluxcore.Scene. Returns (scene, width, height,
    max_depth)."""
    r, cam = cfg["render"], cfg["camera"]
    w, h = r["width"], r["height"]
    scene = pyluxcore.Scene()
    p = pyluxcore.Properties()

    # Camera. LuxCore's perspective `fieldofview` is in degrees over the default screen
    # window's unit half-extent, which is the SMALLER image axis ([-aspect, aspect] x
    # [-1, 1] for a wide image): Mitsuba's fov_axis = "smaller". Verified here only on
    # this square image (edges line up with the reference to the pixel).
    if cam.get("fov_axis", "smaller") not in ("smaller", "x" if w <= h else "y"):
        sys.exit("only fov_axis = smaller (or the equivalent axis) is mapped")
    p.Set(pyluxcore.Property("scene.camera.type", "perspective"))
    p.Set(pyluxcore.Property("scene.camera.lookat.orig", cam["position"]))
    p.Set(pyluxcore.Property("scene.camera.lookat.target", cam["target"]))
    p.Set(pyluxcore.Property("scene.camera.up", cam["up"]))
    p.Set(pyluxcore.Property("scene.camera.fieldofview", float(cam["fov"])))
    # LuxCore maps film y to raster y as `height - filmY - 1` (not `height - filmY`;
    # camera.cpp GenerateRay and GetSamplePosition alike), which moves the whole image
    # down by one pixel against Mitsuba/penumbra. Undo it by sliding the default screen
    # window ([-aspect, aspect] x [-1, 1], or [-1, 1] x [-1/aspect, 1/aspect]) down by
    # one pixel.
    ax, ay = (w / h, 1.0) if w >= h else (1.0, h / w)
    dy = 2.0 * ay / h
    p.Set(pyluxcore.Property("scene.camera.screenwindow", [-ax, ax, -ay - dy, ay - dy]))

    # Materials: penumbra `diffuse` -> LuxCore `matte` (Lambertian, kd = reflectance).
    # LuxCore's matte reflects on both sides, as penumbra's diffuse does by default
    # (two_sided = true). Constant colours are used as-is (linear RGB).
    mats = {}
    for m in cfg["material"]:
        if m["type"] != "diffuse":
            sys.exit(f"material {m['name']}: only `diffuse` is mapped")
        mats[m["name"]] = m["reflectance"]
        p.Set(pyluxcore.Property(f"scene.materials.{m['name']}.type", "matte"))
        p.Set(pyluxcore.Property(f"scene.materials.{m['name']}.kd", mats[m["name"]]))

    # Shapes: every [[shape]] of type "mesh" -> DefineMesh + one object.
    for i, s in enumerate(cfg["shape"]):
        if s["type"] != "mesh":
            sys.exit(f"shape {i}: only `mesh` is mapped")
        mesh = f"mesh{i}"
        verts = [tuple(map(float, v)) for v in s["positions"]]
        tris = [tuple(map(int, t)) for t in s["indices"]]
        # name, vertices, triangles, normals, uvs, colours, alphas (none: flat shading,
        # the geometric normal follows the counter-clockwise winding like penumbra's).
        scene.DefineMesh(mesh, verts, tris, None, None, None, None)
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
                sys.exit("two-sided emitters are not mapped")
            light = f"{mat}_emitter{i}"
            pre = f"scene.materials.{light}"
            p.Set(pyluxcore.Property(f"{pre}.type", "matte"))
            p.Set(pyluxcore.Property(f"{pre}.kd", mats[mat]))
            p.Set(pyluxcore.Property(f"{pre}.emission", [float(x) for x in s["emission"]]))
            p.Set(pyluxcore.Property(f"{pre}.emission.gain", [1.0, 1.0, 1.0]))
            p.Set(pyluxcore.Property(f"{pre}.emission.power", 0.0))
            p.Set(pyluxcore.Property(f"{pre}.emission.efficiency", 0.0))
            p.Set(pyluxcore.Property(f"{pre}.emission.normalizebycolor", False))
            mat = light
        p.Set(pyluxcore.Property(f"scene.objects.obj{i}.shape", mesh))
        p.Set(pyluxcore.Property(f"scene.objects.obj{i}.material", mat))
    scene.Parse(p)
    return scene, w, h, r.get("max_depth", 5)


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
        # came out 12% / 5% / 3% (R/G/B) brighter than the reference on this scene,
        # and within 1% with it off (see README.md). RR never fires at depth >= this.
        P("path.russianroulette.depth", max(eye, light) + 1)
    # PATHCPU keeps LuxCore's default Russian roulette (depth 3, cap 0.5): it matches.
    # Reconstruction filter: LuxCore's GAUSSIAN is exp(-alpha x^2) - exp(-alpha r^2),
    # separable, with `width` the radius in pixels; alpha = 1 / (2 sigma^2).
    if flt.get("type") == "gaussian":
        sigma = float(flt.get("sigma", 0.5))
        P("film.filter.type", "GAUSSIAN")
        P("film.filter.width", float(flt.get("radius", 2.0)))
        P("film.filter.gaussian.alpha", 1.0 / (2.0 * sigma * sigma))
    elif flt.get("type") == "box":
        P("film.filter.type", "BOX")
        P("film.filter.width", float(flt.get("radius", 0.5)))
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


def write_exr(path, rgb):
    h, w, _ = rgb.shape
    channels = {c: np.ascontiguousarray(rgb[:, :, i], dtype=np.float32)
                for i, c in enumerate("RGB")}
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, channels) as f:
        f.write(str(path))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("seconds", type=float, help="wall-clock render budget (batch.halttime)")
    ap.add_argument("out", help="output OpenEXR (linear RGB float)")
    ap.add_argument("--engine", default="BIDIRCPU", choices=["BIDIRCPU", "PATHCPU"])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--sampler", default="SOBOL", choices=["SOBOL", "RANDOM"])
    ap.add_argument("--scene", default=str(DEFAULT_SCENE))
    ap.add_argument("--eye-depth", type=int, help="BIDIRCPU path.maxdepth override")
    ap.add_argument("--light-depth", type=int, help="BIDIRCPU light.maxdepth override")
    ap.add_argument("--prop", action="append", default=[], metavar='"KEY = VALUE"',
                    help="extra LuxCore render-config property (repeatable)")
    ap.add_argument("--verbose", action="store_true", help="show LuxCore's log")
    a = ap.parse_args()

    pyluxcore.Init((lambda msg: print(msg, file=sys.stderr)) if a.verbose else (lambda msg: None))
    cfg = tomllib.loads(Path(a.scene).read_text())
    scene, w, h, max_depth = build_scene(cfg)
    config = render_config(scene, w, h, max_depth, a, cfg["render"].get("filter", {}))

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
    film = session.GetFilm()
    rgb = np.zeros((h, w, 3), dtype=np.float32)
    film.GetOutputFloat(pyluxcore.FilmOutputType.RGB, rgb)
    rgb = rgb[::-1]                       # LuxCore's buffer has row 0 at the bottom
    write_exr(a.out, rgb)
    sps = stats.Get("stats.renderengine.total.samplesec").GetFloat()
    print(f"engine {a.engine} sampler {a.sampler} threads {a.threads}: "
          f"{passes} spp in {elapsed:.2f} s ({sps / 1e6:.2f} M samples/s), "
          f"mean RGB {rgb.reshape(-1, 3).mean(0).round(5).tolist()} -> {a.out}")
    # pyluxcore 2.11 segfaults while the interpreter tears its objects down; all work
    # is done and written, so leave without running the finalisers.
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)


if __name__ == "__main__":
    main()
