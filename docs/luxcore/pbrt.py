#!/usr/bin/env python3
"""Render a pbrt-v4 scene with LuxCore (pyluxcore 2.11) for an equal-time comparison.

    python3 docs/luxcore/pbrt.py SECONDS OUT.exr --scene FILE.pbrt [--res WxH]
        [--engine BIDIRCPU|PATHCPU] [--threads 2] [--sampler SOBOL|RANDOM]
        [--eye-depth N] [--light-depth N] [--exact-spot] [--prop "k = v"]... [--verbose]

Maps the subset of pbrt-v4 that pbrt-veach-bidir and pbrt-caustic-glass use, read as
penumbra's pbrt reader (crates/scene/src/formats/pbrt) reads it; anything else stops with
a message. Render settings, EXR and printout are scene.py's (imported from beside this
file). README.md lists the mapping and what does not match.
"""
import argparse
import math
import re
import sys
from pathlib import Path

# numpy and OpenEXR BEFORE pyluxcore (see scene.py, which imports pyluxcore quietly).
import numpy as np
import OpenEXR  # noqa: F401

sys.path.insert(0, str(Path(__file__).resolve().parent))
from scene import camera_props, common_args, pyluxcore, render_and_exit, render_config  # noqa: E402

KNOWN = {"LookAt", "Transform", "ConcatTransform", "WorldBegin", "AttributeBegin",
         "AttributeEnd", "NamedMaterial", "Camera", "Film", "Sampler", "Integrator",
         "PixelFilter", "MakeNamedMaterial", "Material", "AreaLightSource", "LightSource",
         "Shape"}   # directives mapped (each in its place: before or after WorldBegin)
TOKEN = re.compile(r'"[^"]*"|\[|\]|#[^\n]*|[^\s\[\]"#]+')


def directives(path):
    """(name, argument tokens, line) for each directive of a pbrt file."""
    text, line, pos, cur = Path(path).read_text(), 1, 0, None
    for m in TOKEN.finditer(text):
        line, pos, t = line + text.count("\n", pos, m.start()), m.start(), m.group()
        if t.startswith("#"):
            continue
        if re.fullmatch(r"[A-Z][A-Za-z]*", t):
            if cur:
                yield cur
            cur = (t, [], line)
        elif cur is None:
            sys.exit(f"{path}:{line}: expected a directive, found {t}")
        else:
            cur[1].append(t)
    if cur:
        yield cur


def value(t):
    if t.startswith('"'):
        return {'"true"': True, '"false"': False}.get(t, t[1:-1])
    return {"true": True, "false": False}[t] if t in ("true", "false") else float(t)


def numbers(args, n, where):
    v = [value(t) for t in args if t not in "[]"]
    if len(v) != n or not all(isinstance(x, float) for x in v):
        sys.exit(f"{where}: expected {n} numbers")
    return v


class Params:
    """A directive's leading string (`kind`) and its "type name" value lists; done()
    stops on any parameter that nobody read."""

    def __init__(self, args, where):
        self.where, self.d, self.used = where, {}, set()
        lead = bool(args) and args[0].startswith('"') and len(args[0].split()) == 1
        self.kind, i = (value(args[0]), 1) if lead else (None, 0)
        while i < len(args):
            decl = args[i].strip('"').split()
            if len(decl) != 2 or i + 1 >= len(args):
                sys.exit(f"{where}: cannot read parameter {args[i]}")
            j = args.index("]", i + 1) if args[i + 1] == "[" else i + 1
            vals = args[i + 2:j] if args[i + 1] == "[" else [args[i + 1]]
            self.d[decl[1]], i = (decl[0], [value(v) for v in vals]), j + 1

    def get(self, name, default=None):
        if name not in self.d:
            return default
        self.used.add(name)
        if self.d[name][0] == "texture":
            sys.exit(f"{self.where}: `{name}`: textures are not mapped")
        return self.d[name][1]

    def one(self, name, default):
        return self.get(name, [default])[0]

    def color(self, name, default, light=False):
        """rgb, a grey float (not for lights) or a blackbody (unit luminance)."""
        v, ty = self.get(name), self.d.get(name, [None])[0]
        if v is None:
            return list(default)
        if ty in ("rgb", "color") and len(v) == 3 or ty == "float" and len(v) == 1 and not light:
            return [float(x) for x in v] * (3 if ty == "float" else 1)
        if ty == "blackbody" and len(v) == 1:
            return blackbody(v[0]).tolist()
        sys.exit(f"{self.where}: `{ty} {name}` is not mapped (rgb, float or blackbody)")

    def done(self, ignore=()):
        left = sorted(set(self.d) - self.used - set(ignore))
        if left:
            sys.exit(f"{self.where}: parameter(s) {', '.join(left)} not mapped")


def blackbody(kelvin):
    """Linear sRGB of unit luminance (pbrt-v4 divides a light's spectrum by its
    luminance), computed as penumbra's reader does (params.rs blackbody())."""
    nm = np.arange(360.0, 831.0)
    lam, c, h, kb = nm * 1e-9, 299792458.0, 6.62607015e-34, 1.380649e-23
    planck = 2 * h * c * c / (lam ** 5 * (np.exp(h * c / (lam * kb * kelvin)) - 1))

    def lobe(mean, a, b):
        return np.exp(-0.5 * ((nm - mean) * np.where(nm < mean, a, b)) ** 2)
    xyz = np.array([
        1.056 * lobe(599.8, .0264, .0323) + .362 * lobe(442.0, .0624, .0374)
        - .065 * lobe(501.1, .0490, .0382),
        .821 * lobe(568.8, .0213, .0247) + .286 * lobe(530.9, .0613, .0322),
        1.217 * lobe(437.0, .0845, .0278) + .681 * lobe(459.0, .0385, .0725)]) @ planck
    rgb = np.array([[3.240479, -1.537150, -0.498535], [-0.969256, 1.875991, 0.041556],
                    [0.055648, -0.204043, 1.057311]]) @ xyz
    return rgb / (rgb @ [0.2126, 0.7152, 0.0722])


def read_ply(path):
    """Positions, normals (or None) and triangles of a binary little-endian PLY of
    all-triangle or all-quad faces."""
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    types = {"float": "<f4", "float32": "<f4", "double": "<f8", "uchar": "u1",
             "uint8": "u1", "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4"}
    elems = []
    for t in (line.split() for line in data[:end].decode().splitlines()):
        if t[:1] == ["format"] and t[1] != "binary_little_endian":
            sys.exit(f"{path}: only binary_little_endian PLY is mapped")
        if t[:1] == ["element"]:
            elems.append((t[1], int(t[2]), []))
        if t[:1] == ["property"]:
            elems[-1][2].append(t[1:])
    pos, v, f = end, None, None
    for name, n, props in elems:
        if name == "vertex":
            if not {p[-1] for p in props} <= set("x y z nx ny nz u v s t".split()):
                sys.exit(f"{path}: vertex properties other than x y z nx ny nz u v")
            dt = np.dtype([(p[1], types[p[0]]) for p in props])
            v = np.frombuffer(data, dt, n, pos)
        elif name == "face" and len(props) == 1 and props[0][0] == "list":
            k = int(np.frombuffer(data, types[props[0][1]], 1, pos)[0])
            dt = np.dtype([("n", types[props[0][1]]), ("i", types[props[0][2]], k)])
            f = np.frombuffer(data, dt, n, pos)
            if k not in (3, 4) or (f["n"] != k).any():
                sys.exit(f"{path}: faces must be all triangles or all quads")
            f = f["i"] if k == 3 else np.concatenate([f["i"][:, [0, 1, 2]], f["i"][:, [0, 2, 3]]])
        else:
            sys.exit(f"{path}: PLY element {name!r} is not mapped")
        pos += dt.itemsize * n
    p = np.stack([v["x"], v["y"], v["z"]], -1).astype(float)
    nrm = np.stack([v["nx"], v["ny"], v["nz"]], -1).astype(float) if "nx" in v.dtype.names else None
    return p, nrm, f.astype(np.int64)


def look_at(eye, look, up):
    """pbrt's LookAt: camera-from-world, the camera's x axis cross(up, dir)."""
    d = (np.array(look) - eye) / np.linalg.norm(np.array(look) - eye)
    right = np.cross(np.array(up) / np.linalg.norm(up), d)
    right /= np.linalg.norm(right)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = right, np.cross(d, right), d, eye
    return np.linalg.inv(m)


def roughness(p):
    """pbrt-v4's roughness as GGX alpha: sqrt when remaproughness (the default)."""
    r = p.one("roughness", 0.0)
    u, v, remap = p.one("uroughness", r), p.one("vroughness", r), p.one("remaproughness", True)
    return [math.sqrt(max(x, 0.0)) if remap else max(x, 0.0) for x in (u, v)]


def material(kind, p):
    """A pbrt-v4 material as LuxCore material properties (README.md: the differences)."""
    if kind == "diffuse":
        m = {"type": "matte", "kd": p.color("reflectance", [0.5] * 3)}
    elif kind == "dielectric":
        eta = p.get("eta", [1.5])
        if len(eta) != 1 or not isinstance(eta[0], float) or any(roughness(p)):
            sys.exit(f"{p.where}: only smooth dielectrics with a number `eta` are mapped")
        m = {"type": "glass", "kr": [1.0] * 3, "kt": [1.0] * 3,
             "interiorior": eta[0], "exteriorior": 1.0}
    elif kind == "conductor":
        # metal2 (metal2.cpp; SchlickDistribution_* in materialdefs.cpp): with
        # r = uroughness * vroughness, D = r / (pi (1 + (r - 1) cos^2)^2), i.e. GGX with
        # alpha = uroughness for u = v: pbrt's alpha is LuxCore's uroughness. Its masking
        # is Schlick's G1 = cos / (cos (1 - r) + r), not Smith's. Fresnel: exact, n and k.
        au, av = roughness(p)
        if not (au and av) or "eta" not in p.d or "k" not in p.d:
            sys.exit(f"{p.where}: only rough conductors with `eta` and `k` are mapped")
        m = {"type": "metal2", "n": p.color("eta", []), "k": p.color("k", []),
             "uroughness": au, "vroughness": av}
    elif kind == "coateddiffuse":
        # glossy2: a Schlick-Fresnel GGX coating (F0 from `index`, ks = 1) over kd with
        # (1 - S(wi.h)) kd / pi. penumbra reads coateddiffuse as Mitsuba's roughplastic
        # (exact Fresnel, (1 - F_i)(1 - F_o) rho / (pi eta^2 (1 - F_dr))): same albedo
        # at normal incidence, different angular shape; README.md has the numbers.
        au, av = roughness(p)
        if p.one("albedo", 0.0) != 0 or p.one("g", 0.0) != 0:
            sys.exit(f"{p.where}: a scattering coating (albedo, g) is not mapped")
        p.get("thickness"), p.get("maxdepth"), p.get("nsamples")  # ignored, as penumbra
        m = {"type": "glossy2", "kd": p.color("reflectance", [0.5] * 3), "ks": [1.0] * 3,
             "index": float(p.one("eta", 1.5)), "uroughness": max(au, 1e-4),
             "vroughness": max(av, 1e-4), "multibounce": False}
    else:
        sys.exit(f"{p.where}: material {kind!r} is not mapped")
    p.done(ignore=("type",))
    return m


def spot_light(name, p, ratio, exact, scene):
    """pbrt-v4's spot: I scale smoothstep(cos t; cos coneangle, cos(coneangle - conedelta))
    W/sr. LuxCore's `spot` differs (spotlight.cpp: I falloff^4 / cos t, see README.md);
    --exact-spot bakes pbrt's profile into a `projection` light's map (intensity = gain
    map, projectionlight.cpp), exact but biased in BIDIRCPU (main() refuses it there)."""
    fr, to = p.get("from", [0.0] * 3), p.get("to", [0.0, 0.0, 1.0])
    cone, delta = p.one("coneangle", 30.0), p.one("conedelta", 5.0)
    color = (np.array(p.color("I", [1.0] * 3, light=True)) * p.one("scale", 1.0) * ratio)
    if p.one("power", -1.0) > 0:
        sys.exit(f"{p.where}: a spot's `power` is not mapped")
    p.done()
    props = {"position": fr, "target": to, "color": color.tolist(), "gain": [1.0] * 3,
             "power": 0.0, "efficency": 0.0}   # LuxCore's spelling; 0: no normalisation
    if not exact:
        return {**props, "type": "spot", "coneangle": cone, "conedeltaangle": delta}
    n, t = 1024, math.tan(math.radians(cone))
    x = (np.arange(n) + 0.5) / n * 2 * t - t
    cos_t = 1 / np.sqrt(1 + x[None, :] ** 2 + x[:, None] ** 2)
    c0, c1 = math.cos(math.radians(cone)), math.cos(math.radians(max(cone - delta, 0)))
    s = np.clip((cos_t - c0) / max(c1 - c0, 1e-9), 0, 1)
    img = np.repeat((s * s * (3 - 2 * s)).astype(np.float32)[:, :, None], 3, 2)
    scene.DefineImageMap(f"{name}_profile", np.ascontiguousarray(img), 1.0, 3, n, n)
    # pyluxcore 2.11 ignores a projection light's `color` (measured): the colour is `gain`.
    return {**props, "type": "projection", "fov": 2 * cone, "mapfile": f"{name}_profile",
            "gain": color.tolist(), "color": [1.0] * 3}


def define_shape(scene, mesh, p, path):
    """A plymesh or trianglemesh as a LuxCore mesh `mesh`."""
    if p.kind == "plymesh":
        pts, nrm, tris = read_ply(Path(path).parent / p.one("filename", ""))
    elif p.kind == "trianglemesh":
        pts = np.reshape(p.get("P", []), (-1, 3))
        tris = np.reshape(p.get("indices", [0, 1, 2]), (-1, 3)).astype(np.int64)
        nrm = None if "N" not in p.d else np.reshape(p.get("N"), (-1, 3))
        p.get("uv")  # no textures: not needed
    else:
        sys.exit(f"{p.where}: shape {p.kind!r} is not mapped")
    p.done()
    if nrm is not None:
        # pbrt-v4 turns a triangle's geometric normal (and so an area light's front) to
        # the side of the shading normals; LuxCore's is cross(p1-p0, p2-p0), like pbrt's
        # without normals: rewind the triangles whose winding disagrees (none here).
        ng = np.cross(pts[tris[:, 1]] - pts[tris[:, 0]], pts[tris[:, 2]] - pts[tris[:, 0]])
        flip = np.einsum("ij,ij->i", ng, nrm[tris].sum(1)) < 0
        tris[flip] = tris[flip][:, ::-1]
    scene.DefineMesh(mesh, [tuple(v) for v in pts.tolist()], [tuple(t) for t in tris.tolist()],
                     None if nrm is None else [tuple(v) for v in nrm.tolist()], None, None, None)


def build(path, res, exact_spot):
    """Read the pbrt file into a pyluxcore.Scene; returns it with the film size, the max
    depth in path segments, the filter (as scene.py takes it) and whether to mirror."""
    scene, props, ctm, world, depth, w, h = pyluxcore.Scene(), {}, np.eye(4), False, 5, 1280, 720
    flt, cam, iso, shutter = {"type": "gaussian", "radius": 1.5, "sigma": 0.5}, None, 100.0, 1.0
    named, state, stack, count = {}, {"mat": None, "area": None}, [], 0
    for name, args, line in directives(path):
        where = f"{path}:{line}: {name}"
        if name not in KNOWN:
            sys.exit(f"{where}: not mapped")
        if name in ("LookAt", "Transform", "ConcatTransform") and not world:
            if name == "LookAt":
                ctm = ctm @ look_at(*np.reshape(numbers(args, 9, where), (3, 3)))
            else:  # 16 numbers, column by column (pbrt transposes them on reading)
                m = np.reshape(numbers(args, 16, where), (4, 4)).T
                ctm = m if name == "Transform" else ctm @ m
            continue
        if name == "WorldBegin":
            # pbrt-v4's sensor scales the image by exposure time x iso / 100 (caustic-
            # glass: 1.5); penumbra's reader scales every emitter by it: so do we.
            world, ctm, ratio = True, np.eye(4), shutter * iso / 100.0
            continue
        if name in ("AttributeBegin", "AttributeEnd", "NamedMaterial") and world:
            if name == "AttributeBegin":
                stack.append(dict(state))
            elif name == "AttributeEnd":
                state = stack.pop() if stack else sys.exit(f"{where}: unbalanced")
            else:
                state["mat"] = named.get(value(args[0])) or sys.exit(f"{where}: unknown name")
            continue
        p = Params(args, where)
        if name == "Camera" and not world:
            if p.kind != "perspective":
                sys.exit(f"{where}: camera {p.kind!r} is not mapped")
            cam = (np.linalg.inv(ctm), p.one("fov", 90.0))
            shutter = p.one("shutterclose", 1.0) - p.one("shutteropen", 0.0)
            p.done()
        elif name == "Film" and not world:
            if p.kind != "rgb":
                sys.exit(f"{where}: film {p.kind!r} is not mapped")
            w, h = int(p.one("xresolution", 1280)), int(p.one("yresolution", 720))
            iso = p.one("iso", 100.0)
            p.done(ignore=("filename",))  # ours is OUT.exr
        elif name in ("Sampler", "Integrator") and not world:
            # Render hints: the sampler is --sampler, the algorithm --engine. pbrt's
            # maxdepth (default 5) counts bounces, scene.py's max_depth path segments:
            # + 1, as penumbra's reader does.
            depth = int(p.one("maxdepth", 5)) if name == "Integrator" else depth
        elif name == "PixelFilter" and not world:
            r = max(p.one("xradius", 0.0), p.one("yradius", 0.0))
            if p.kind == "box":
                flt = {"type": "box", "radius": r or 0.5}
            elif p.kind == "gaussian":
                flt = {"type": "gaussian", "radius": r or 1.5, "sigma": p.one("sigma", 0.5)}
            elif p.kind == "triangle":
                # LuxCore has no tent. Its GAUSSIAN of the same radius r, exp(-a x^2) -
                # exp(-a r^2), is the least-squares fit at a = 1.65 / r^2 (README.md).
                r = r or 2.0
                flt = {"type": "gaussian", "radius": r, "sigma": r / math.sqrt(3.3)}
            else:
                sys.exit(f"{where}: filter {p.kind!r} is not mapped")
            p.done()
        elif name in ("MakeNamedMaterial", "Material") and world:
            count += 1
            mat = f"mat{count}"
            kind = p.one("type", None) if name == "MakeNamedMaterial" else p.kind
            for k, v in material(kind, p).items():
                props[f"scene.materials.{mat}.{k}"] = v
            if name == "Material":
                state["mat"] = named[mat] = mat
            else:
                named[p.kind] = mat
        elif name == "AreaLightSource" and world:
            if p.kind != "diffuse" or p.one("twosided", False):
                sys.exit(f"{where}: only one-sided `diffuse` area lights are mapped")
            state["area"] = (np.array(p.color("L", [1.0] * 3, light=True))
                             * p.one("scale", 1.0) * ratio).tolist()
            p.done()
        elif name == "LightSource" and world and p.kind == "spot":
            count += 1
            for k, v in spot_light(f"spot{count}", p, ratio, exact_spot, scene).items():
                props[f"scene.lights.spot{count}.{k}"] = v
        elif name == "Shape" and world:
            count += 1
            define_shape(scene, f"mesh{count}", p, path)
            mat = state["mat"]
            if mat is None:  # pbrt's default material: diffuse 0.5
                mat = named.setdefault("", "default")
                props.update({"scene.materials.default.type": "matte",
                              "scene.materials.default.kd": [0.5] * 3})
            if state["area"] is not None:
                # As scene.py: a copy of the surface's material that emits radiance L
                # (no power normalisation), on the front (geometric normal) side only.
                light = f"{mat}_emitter{count}"
                for k, v in list(props.items()):
                    if k.startswith(f"scene.materials.{mat}."):
                        props[k.replace(f".{mat}.", f".{light}.")] = v
                for k, v in (("emission", state["area"]), ("emission.gain", [1.0] * 3),
                             ("emission.power", 0.0), ("emission.efficiency", 0.0),
                             ("emission.normalizebycolor", False)):
                    props[f"scene.materials.{light}.{k}"] = v
                mat = light
            props[f"scene.objects.obj{count}.shape"] = f"mesh{count}"
            props[f"scene.objects.obj{count}.material"] = mat
        else:
            sys.exit(f"{where} {p.kind or ''}: not mapped " + ("here" if name != "LightSource"
                                                                else "(only spot lights)"))
    if cam is None:
        sys.exit(f"{path}: no Camera")
    if res:
        w, h = map(int, res.lower().split("x"))
    # pbrt's camera space: +z forward, +y up, +x to the image's right. LuxCore's look-at
    # puts cross(forward, up) on the right; where pbrt's +x is the other way (LookAt and
    # veach-bidir's Transform: x = cross(up, forward), left-handed) the image is flipped
    # back after rendering (exact: the screen window is symmetric in x; LuxCore's
    # one-pixel offset, fixed by camera_props, is vertical). pbrt's fov spans the shorter
    # image axis, as LuxCore's fieldofview does.
    c2w, fov = cam
    a = c2w[:3, :3]
    if not np.allclose(a.T @ a, np.eye(3), atol=1e-3):
        sys.exit(f"{path}: a camera transform with scale or shear is not mapped")
    eye, fwd, up = c2w[:3, 3], a[:, 2], a[:, 1]
    mirror = float(np.dot(a[:, 0], np.cross(fwd, up))) < 0
    cp = camera_props({"position": eye.tolist(), "target": (eye + fwd).tolist(),
                       "up": up.tolist(), "fov": fov, "fov_axis": "smaller"}, w, h)
    pp = pyluxcore.Properties()
    for k, v in {**cp, **props}.items():
        pp.Set(pyluxcore.Property(k, v))
    scene.Parse(pp)
    return scene, w, h, depth + 1, flt, mirror


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("seconds", type=float, help="wall-clock render budget (batch.halttime)")
    ap.add_argument("out", help="output OpenEXR (linear RGB float)")
    ap.add_argument("--scene", required=True, help="pbrt-v4 scene file")
    ap.add_argument("--res", help="WxH, overrides the Film resolution like penumbra's")
    ap.add_argument("--exact-spot", action="store_true",
                    help="pbrt's spot profile via a projection light (PATHCPU only)")
    common_args(ap)
    a = ap.parse_args()
    if a.exact_spot and a.engine != "PATHCPU":
        # Its Illuminate() returns emission pdf 0, so BIDIRCPU's MIS counts direct light
        # twice (measured 1.90x on a test plane).
        sys.exit("--exact-spot: LuxCore's projection light is biased in BIDIRCPU")
    pyluxcore.Init((lambda msg: print(msg, file=sys.stderr)) if a.verbose else (lambda msg: None))
    scene, w, h, max_depth, flt, mirror = build(a.scene, a.res, a.exact_spot)
    render_and_exit(render_config(scene, w, h, max_depth, a, flt), w, h, a, mirror)


if __name__ == "__main__":
    main()
