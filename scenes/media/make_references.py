"""Reference images of the media and spectral test scenes, rendered by Mitsuba 3.

usage: ~/.cache/penumbra-anchors/venv/bin/python scenes/media/make_references.py [--res 64] [--spp 16384] [--scenes a,b]
(after `../shared/anchors/run.sh setup`; DRJIT_LIBLLVM_PATH as run.sh sets it)

For each scene: the reference (--spp samples in chunks of 1024 with distinct seeds) goes to
tests/data/DIR/NAME.exr, and Mitsuba's own relMSE against it at 256 spp (the mean over four
seeds that are not the reference's) and channel means to tests/data/DIR/NAME.json, which
tests/media_mitsuba.rs and tests/spectral_mitsuba.rs hold Penumbra to. The media scenes
render with llvm_ad_rgb; the spectral ones with llvm_ad_spectral.
"""
import argparse, json, os
import numpy as np
import mitsuba as mi

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
# name: (scene file relative to the repository, Mitsuba variant, folder under tests/data)
SCENES = {
    "fog-cbox": ("scenes/media/fog-cbox.xml", "llvm_ad_rgb", "media"),
    "media-spheres": ("scenes/media/media-spheres.xml", "llvm_ad_rgb", "media"),
    "cloud-cbox": ("scenes/media/cloud-cbox.xml", "llvm_ad_rgb", "media"),
    "cbox-spectral": ("../shared/scenes/mitsuba-cbox/cbox-spectral.xml", "llvm_ad_spectral", "spectral"),
    "metals-cbox": ("scenes/spectral/metals-cbox.xml", "llvm_ad_spectral", "spectral"),
    "glass-cbox": ("scenes/spectral/glass-cbox.xml", "llvm_ad_spectral", "spectral"),
}


def render(name, res, spp, seed):
    path, variant, _ = SCENES[name]
    mi.set_variant(variant)
    scene = mi.load_file(os.path.join(ROOT, path), res=str(res), spp=str(spp))
    return np.array(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)[..., :3]


def relmse(x, ref):
    return float(np.mean((x - ref) ** 2 / (ref ** 2 + 1e-2)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument("--spp", type=int, default=16384)
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated names (all by default)")
    a = ap.parse_args()
    for name in a.scenes.split(","):
        path, variant, folder = SCENES[name]
        out = os.path.join(ROOT, "tests", "data", folder)
        os.makedirs(out, exist_ok=True)
        chunks = max(1, a.spp // 1024)
        ref = sum(render(name, a.res, min(a.spp, 1024), 1000 + i) for i in range(chunks)) / chunks
        mi.Bitmap(ref.astype(np.float32)).write(os.path.join(out, f"{name}.exr"))
        errors = [relmse(render(name, a.res, 256, s), ref) for s in (1, 2, 3, 4)]
        info = {
            "scene": path,
            "res": a.res,
            "reference_spp": chunks * min(a.spp, 1024),
            "mitsuba": mi.__version__,
            "variant": variant,
            "mitsuba_relmse_256spp": float(np.mean(errors)),
            "mitsuba_relmse_256spp_seeds": errors,
            "means": [float(m) for m in ref.reshape(-1, 3).mean(axis=0)],
        }
        json.dump(info, open(os.path.join(out, f"{name}.json"), "w"), indent=1)
        print(name, info, flush=True)


if __name__ == "__main__":
    main()
