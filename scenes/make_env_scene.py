#!/usr/bin/env python3
"""Writes scenes/sky.pfm, the small synthetic HDR environment of scenes/glossy-env.toml:
a latitude-longitude map (u = phi / 2 pi across, v = theta / pi down) with a blue sky
fading to a pale horizon, dark ground, a sun (radiance 3000, about 2 pixels wide) and two
bright rectangular panels (radiance 40), so that a turning map moves sharp, strong
features across a glossy object. Public domain (made here, no outside data)."""
import math
import struct

W, H = 128, 64
rows = []
for y in range(H):
    row = []
    for x in range(W):
        u, v = (x + 0.5) / W, (y + 0.5) / H
        theta = v * math.pi
        if theta < math.pi / 2:
            t = theta / (math.pi / 2)
            c = [0.25 + 0.6 * t, 0.4 + 0.45 * t, 0.85 + 0.05 * t]
        else:
            c = [0.12, 0.1, 0.08]
        # Sun at theta 45 degrees, u 0.30.
        du = min(abs(u - 0.30), 1 - abs(u - 0.30)) * W
        dv = (v - 0.25) * H
        if du * du + dv * dv <= 1.2:
            c = [3000.0, 2800.0, 2400.0]
        # Two panels near the horizon.
        for (u0, u1, v0, v1) in [(0.60, 0.68, 0.30, 0.42), (0.85, 0.90, 0.20, 0.45)]:
            if u0 <= u <= u1 and v0 <= v <= v1:
                c = [40.0, 38.0, 34.0]
        row.append(c)
    rows.append(row)

with open("scenes/sky.pfm", "wb") as f:
    f.write(b"PF\n%d %d\n-1.0\n" % (W, H))
    # PFM stores rows bottom to top.
    for row in reversed(rows):
        for c in row:
            f.write(struct.pack("<3f", *c))
