"""The triangle meshes of a native scene file as one binary PLY (for Embree)."""
import struct, sys, tomllib

scene, out = sys.argv[1], sys.argv[2]
desc = tomllib.load(open(scene, "rb"))
positions, faces = [], []
for shape in desc.get("shape", []):
    if shape.get("type") != "mesh":
        continue
    base = len(positions)
    positions += shape["positions"]
    faces += [[base + i for i in tri] for tri in shape["indices"]]
with open(out, "wb") as f:
    f.write(
        f"ply\nformat binary_little_endian 1.0\nelement vertex {len(positions)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar uint vertex_indices\nend_header\n".encode()
    )
    for p in positions:
        f.write(struct.pack("<3f", *p))
    for t in faces:
        f.write(struct.pack("<B3I", 3, *t))
