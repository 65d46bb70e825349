"""Reference images of the media test scenes, rendered by Mitsuba 3 (llvm_ad_rgb, volpath).

usage: ~/.cache/penumbra-anchors/venv/bin/python scenes/media/make_references.py [--res 64] [--spp 16384] [--scenes a,b]
(after `../shared/anchors/run.sh setup`; DRJIT_LIBLLVM_PATH as run.sh sets it)

For each scene: the reference (--spp samples in chunks of 1024 with distinct seeds) goes to
tests/data/media/NAME.exr, and Mitsuba's own relMSE against it at 256 spp (the mean over four
seeds that are not the reference's) and channel means to tests/data/media/NAME.json, which
tests/media_mitsuba.rs holds Penumbra to.
"""
import argparse, json, os
import numpy as np
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")
HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "..", "tests", "data", "media")
SCENES = ["fog-cbox", "media-spheres", "cloud-cbox"]


def render(name, res, spp, seed):
    scene = mi.load_file(os.path.join(HERE, f"{name}.xml"), res=str(res), spp=str(spp))
    return np.array(mi.render(scene, spp=spp, seed=seed), dtype=np.float64)[..., :3]


def relmse(x, ref):
    return float(np.mean((x - ref) ** 2 / (ref ** 2 + 1e-2)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument("--spp", type=int, default=16384)
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated names (all by default)")
    a = ap.parse_args()
    os.makedirs(OUT, exist_ok=True)
    for name in a.scenes.split(","):
        chunks = max(1, a.spp // 1024)
        ref = sum(render(name, a.res, min(a.spp, 1024), 1000 + i) for i in range(chunks)) / chunks
        mi.Bitmap(ref.astype(np.float32)).write(os.path.join(OUT, f"{name}.exr"))
        errors = [relmse(render(name, a.res, 256, s), ref) for s in (1, 2, 3, 4)]
        info = {
            "scene": f"scenes/media/{name}.xml",
            "res": a.res,
            "reference_spp": chunks * min(a.spp, 1024),
            "mitsuba": mi.__version__,
            "variant": "llvm_ad_rgb",
            "mitsuba_relmse_256spp": float(np.mean(errors)),
            "mitsuba_relmse_256spp_seeds": errors,
            "means": [float(m) for m in ref.reshape(-1, 3).mean(axis=0)],
        }
        json.dump(info, open(os.path.join(OUT, f"{name}.json"), "w"), indent=1)
        print(name, info, flush=True)


if __name__ == "__main__":
    main()
