"""Error per sample, seed by seed: Mitsuba 3 (llvm_ad_rgb) and Penumbra render one of the
suite's scenes at the same spp with several seeds each; prints each image's relMSE against
the suite's reference, their means, and where (by image block and by reference brightness)
our error differs from Mitsuba's.

usage (the anchors' Python, after `../shared/anchors/run.sh setup`):
  DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
  ~/.cache/penumbra-anchors/venv/bin/python docs/checks/seed_variance.py \\
      [--scene env-materials] [--seeds 6] [--spp 64] [--bin target/release/penumbra]
"""
import argparse, os, sys, tempfile
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "../../../shared/anchors"))
import mitsuba_suite as ms  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--scene", default="env-materials")
ap.add_argument("--seeds", type=int, default=6)
ap.add_argument("--spp", type=int, default=64)
ap.add_argument("--bin", default=os.path.join(HERE, "../../target/release/penumbra"))
a = ap.parse_args()
xml, refp = ms.SCENES[a.scene]
params = ms.PARAMS.get(a.scene, {})
ref = ms.load_exr(refp or ms.reference(a.scene, xml, 1024, params))
out = tempfile.mkdtemp()
mits = [ms.mitsuba(xml, a.spp, 100 + s, params)[0] for s in range(a.seeds)]
ours = [ms.penumbra(os.path.abspath(a.bin), xml, a.spp, 200 + s, f"{out}/{s}.exr", params)[0] for s in range(a.seeds)]


def errors(imgs):
    return np.stack([((x - ref) ** 2 / (ref ** 2 + 1e-2)).mean(-1) for x in imgs])


em, ep = errors(mits), errors(ours)
print("relMSE Mitsuba", em.mean(axis=(1, 2)).round(6), "mean", em.mean())
print("relMSE ours   ", ep.mean(axis=(1, 2)).round(6), "mean", ep.mean())
print("image means: Mitsuba", np.mean(mits, axis=(0, 1, 2)).round(5), "ours", np.mean(ours, axis=(0, 1, 2)).round(5),
      "reference", ref.mean(axis=(0, 1)).round(5))
h, w = ref.shape[:2]
bh, bw = h // 5, w // 8
print("by block (5 x 8): share of our error, our error / Mitsuba's")
em, ep = em.mean(0), ep.mean(0)
for by in range(5):
    cells = []
    for bx in range(8):
        block = (slice(by * bh, (by + 1) * bh), slice(bx * bw, (bx + 1) * bw))
        cells.append(f"{ep[block].sum() / ep.sum() * 100:4.1f}%:{ep[block].sum() / em[block].sum():4.2f}")
    print("  ".join(cells))
lum = ref.mean(-1)
for lo, hi in [(0, 0.1), (0.1, 0.3), (0.3, 0.6), (0.6, 1.0), (1.0, 3.0), (3.0, np.inf)]:
    m = (lum >= lo) & (lum < hi)
    if m.any():
        print(f"reference brightness [{lo}, {hi}): {m.mean() * 100:5.1f}% of pixels, "
              f"our error / Mitsuba's {ep[m].sum() / em[m].sum():.3f}, share of ours {ep[m].sum() / ep.sum() * 100:.1f}%")
