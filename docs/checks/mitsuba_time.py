"""Times Mitsuba 3 rendering a scene: min and median of three renders after a warm-up (JIT).

usage: DRJIT_LIBLLVM_PATH=... ~/.cache/penumbra-anchors/venv/bin/python docs/checks/mitsuba_time.py SCENE.xml VARIANT
(256x256, 64 spp through the scene's `res` and `spp` parameters)
"""
import sys, time, numpy as np, mitsuba as mi
mi.set_variant(sys.argv[2])
scene = mi.load_file(sys.argv[1], res="256", spp="64")
mi.render(scene, spp=64)  # warm-up (JIT)
ts=[]
for s in range(3):
    t=time.time(); img=mi.render(scene, spp=64, seed=s+1); np.array(img); ts.append(time.time()-t)
print(sys.argv[2], "min %.3f median %.3f" % (min(ts), sorted(ts)[1]))
