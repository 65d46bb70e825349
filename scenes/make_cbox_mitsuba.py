"""Writes scenes/cbox-mitsuba.toml from ../shared/references/mitsuba-cbox/cbox_world.json:
Mitsuba 3's built-in Cornell box with its exact world-space triangles, colours, radiance,
camera and filter. Run from the repository root: python3 scenes/make_cbox_mitsuba.py"""

import json

SRC = "../shared/references/mitsuba-cbox/cbox_world.json"

HEADER = """# Mitsuba 3's built-in Cornell box (`mitsuba.cornell_box()`, Mitsuba 3.9.1), exactly: the
# world-space triangles, colours, radiance, camera and filter of
# ../shared/references/mitsuba-cbox/cbox_scene.md, for comparison with its 16,384-spp
# reference render (`cargo test --test cbox`, docs/path-tracing.md).
# Generated from cbox_world.json by scenes/make_cbox_mitsuba.py.

[render]
width = 256
height = 256
spp = 64
integrator = "path"
max_depth = 8
sampler = "independent"
filter = { type = "gaussian", radius = 2.0, sigma = 0.5 }

[camera]
position = [0.0, 0.0, 3.9]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 39.3077
fov_axis = "smaller"
"""


def main():
    d = json.load(open(SRC))
    out = [HEADER]
    for name, b in d["bsdfs"].items():
        r = b["reflectance"]
        out.append(f'[[material]]\nname = "{name}"\ntype = "diffuse"\nreflectance = [{r[0]}, {r[1]}, {r[2]}]\n')
    for sh in d["shapes"]:
        vs = ", ".join("[" + ", ".join(repr(float(c)) for c in v) + "]" for v in sh["vertices"])
        fs = ", ".join("[" + ", ".join(str(i) for i in t) + "]" for t in sh["faces"])
        s = f'# {sh["id"]}\n[[shape]]\ntype = "mesh"\nmaterial = "{sh["bsdf"]}"\npositions = [{vs}]\nindices = [{fs}]\n'
        if "emitter" in sh:
            r = sh["emitter"]["radiance"]
            s += f"emission = [{r[0]}, {r[1]}, {r[2]}]\n"
        out.append(s)
    open("scenes/cbox-mitsuba.toml", "w").write("\n".join(out))


if __name__ == "__main__":
    main()
