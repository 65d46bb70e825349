"""A procedural cloud as a Mitsuba .vol grid: scenes/media/cloud.vol (40^3, one channel).

usage: python3 scenes/media/make_cloud.py   (needs numpy; deterministic: the same bytes each run)

The density is a few overlapping Gaussian puffs, carved by a sum of sines (a cheap,
seedless turbulence) and faded to zero at the grid's faces, at most 1. The file is the
binary format Mitsuba 3's `gridvolume` reads (see crates/scene/src/formats/vol.rs).
"""
import os, struct
import numpy as np

N = 40
HERE = os.path.dirname(os.path.abspath(__file__))


def density():
    c = (np.arange(N) + 0.5) / N
    z, y, x = np.meshgrid(c, c, c, indexing="ij")  # x fastest in the flattened array
    puffs = [((0.5, 0.45, 0.5), 0.22, 1.0), ((0.3, 0.4, 0.45), 0.15, 0.8),
             ((0.7, 0.42, 0.55), 0.16, 0.8), ((0.5, 0.62, 0.45), 0.14, 0.7),
             ((0.42, 0.3, 0.6), 0.12, 0.6)]
    d = np.zeros_like(x)
    for (px, py, pz), r, w in puffs:
        d += w * np.exp(-((x - px) ** 2 + (y - py) ** 2 + (z - pz) ** 2) / (2 * r * r))
    turb = sum(np.sin(f * 2 * np.pi * (x * a + y * b + z * e) + f) / f
               for f, (a, b, e) in [(3, (1, 0.3, 0.2)), (5, (0.2, 1, 0.4)), (7, (0.5, 0.2, 1)),
                                    (11, (0.7, 0.7, 0.1))])
    d = d * (1 + 0.6 * turb) - 0.25
    edge = np.minimum.reduce([x, 1 - x, y, 1 - y, z, 1 - z])
    d *= np.clip(edge / 0.1, 0, 1)
    d = np.clip(d, 0, None)
    return (d / d.max()).astype("<f4")


def main():
    d = density()
    header = b"VOL" + bytes([3]) + struct.pack("<5i", 1, N, N, N, 1) + struct.pack("<6f", 0, 0, 0, 1, 1, 1)
    with open(os.path.join(HERE, "cloud.vol"), "wb") as f:
        f.write(header + d.tobytes())
    print(f"cloud.vol: {N}^3, mean density {d.mean():.3f}, {np.mean(d > 0):.0%} of cells non-zero")


if __name__ == "__main__":
    main()
