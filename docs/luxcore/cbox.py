#!/usr/bin/env python3
"""Render penumbra's scenes/cbox-mitsuba.toml with LuxCore (pyluxcore 2.11) for an
equal-time comparison.

    python3 docs/luxcore/cbox.py SECONDS OUT.exr [--engine BIDIRCPU|PATHCPU] [--threads 2]
        [--sampler SOBOL|RANDOM] [--scene FILE.toml] [--eye-depth N] [--light-depth N]

The conversion and the render loop live in scene.py beside this file (which takes any
scene it can map via --scene); this wrapper only defaults the scene to the Cornell box.
See README.md for the mapping and its caveats.
"""
from pathlib import Path

import scene  # docs/luxcore/scene.py: imports numpy before pyluxcore, exits with os._exit

if __name__ == "__main__":
    scene.main(str(Path(__file__).resolve().parents[2] / "scenes" / "cbox-mitsuba.toml"))
