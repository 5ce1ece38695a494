#!/usr/bin/env python3
"""Writes a dense test scene: the Cornell box holding a finely tessellated bumpy sphere, so that the preview's cost
can be measured at 10k, 100k or 1M triangles. The files are large, so they are generated, not committed: the
default output folder out/scenes/ is ignored by git. Standard library only; the output is deterministic.

Usage: python3 scripts/make_dense_scene.py --triangles 100000 [--light area|point] [--out DIR]
Writes DIR/dense-<triangles>[-point].gltf with its buffer in a .bin file beside it.
"""

import argparse
import json
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scenes as ms  # noqa: E402  (the Cornell box data and the glTF writer)


def bumpy_sphere(triangles, centre, radius):
    """A UV sphere of about `triangles` triangles whose radius is modulated by a few sine waves (fine relief that casts
    small shadows onto itself), with smooth analytic normals. Returns positions, normals, indices (flat lists)."""
    rings = max(4, int(round(math.sqrt(triangles / 4.0))))
    segments = max(8, int(round(triangles / (2.0 * rings))))
    positions, normals = [], []

    def surface(theta, phi):
        bump = 1.0 + 0.06 * math.sin(9.0 * theta) * math.sin(7.0 * phi) + 0.03 * math.sin(23.0 * phi + 3.0 * theta)
        s = (math.sin(theta) * math.cos(phi), math.cos(theta), math.sin(theta) * math.sin(phi))
        return tuple(centre[i] + radius * bump * s[i] for i in range(3))

    eps = 1e-4
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2.0 * math.pi * s / segments
            p = surface(theta, phi)
            # Normal from the surface's partial derivatives (central differences), outward.
            t0, t1 = max(theta - eps, 1e-6), min(theta + eps, math.pi - 1e-6)
            dt = ms.sub(surface(t1, phi), surface(t0, phi))
            dp = ms.sub(surface(theta, phi + eps), surface(theta, phi - eps))
            n = ms.cross(dp, dt)
            length = math.sqrt(ms.dot(n, n))
            n = ms.normalize(ms.sub(p, centre)) if length < 1e-12 else ms.scale(n, 1.0 / length)
            if ms.dot(n, ms.sub(p, centre)) < 0.0:
                n = ms.scale(n, -1.0)
            positions.append(p)
            normals.append(n)
    indices = []
    row = segments + 1
    for r in range(rings):
        for s in range(segments):
            a, b = r * row + s, r * row + s + 1
            c, d = a + row, b + row
            # Counter-clockwise seen from outside; the pole rows' degenerate triangles are skipped.
            if r != 0:
                indices += [a, b, c]
            if r != rings - 1:
                indices += [b, d, c]
    return positions, normals, indices


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser.add_argument("--triangles", type=int, default=100000, help="triangles of the tessellated object")
    parser.add_argument("--light", choices=["area", "point"], default="area",
                        help="the Cornell box's area light, or a point light (KHR_lights_punctual) in its place")
    parser.add_argument("--out", default=os.path.join(root, "out", "scenes"))
    args = parser.parse_args()
    if args.triangles < 100 or args.triangles > 20000000:
        parser.error("--triangles must lie in [100, 20000000]")

    name = "dense-%d%s" % (args.triangles, "-point" if args.light == "point" else "")
    g = ms.cornell(name, "plain")
    if args.light == "point":
        # Drop the area light's mesh (the last node before the camera) and its material stays unused.
        g.meshes = [m for m in g.meshes if m["name"] != "light"]
        g.nodes = [n for n in g.nodes if n.get("name") != "light"]
        for i, n in enumerate(n for n in g.nodes if "mesh" in n):
            n["mesh"] = i
    white = g.material_index["white"]
    positions, normals, indices = bumpy_sphere(args.triangles, (0.37, 0.33 + 0.14, 0.35), 0.14)
    pos_view = g._view(struct.pack("<%df" % (3 * len(positions)), *[c for p in positions for c in p]), 34962)
    nrm_view = g._view(struct.pack("<%df" % (3 * len(normals)), *[c for n in normals for c in n]), 34962)
    idx_view = g._view(struct.pack("<%dI" % len(indices), *indices), 34963)
    stored = [struct.unpack("<3f", struct.pack("<3f", *p)) for p in positions]
    lo = [min(p[i] for p in stored) for i in range(3)]
    hi = [max(p[i] for p in stored) for i in range(3)]
    pos = g._accessor(pos_view, 5126, len(positions), "VEC3", {"min": lo, "max": hi})
    nrm = g._accessor(nrm_view, 5126, len(normals), "VEC3")
    idx = g._accessor(idx_view, 5125, len(indices), "SCALAR")
    g.meshes.append({"name": "bumpy-sphere", "primitives": [
        {"attributes": {"POSITION": pos, "NORMAL": nrm}, "indices": idx, "material": white, "mode": 4}]})
    g.nodes.append({"name": "bumpy-sphere", "mesh": len(g.meshes) - 1})

    doc = json.loads(g.to_json())
    os.makedirs(args.out, exist_ok=True)
    bin_name = name + ".bin"
    doc["buffers"] = [{"byteLength": len(g.buffer), "uri": bin_name}]
    doc["asset"]["extras"] = {"units": "metres", "triangles": 32 + len(indices) // 3}
    if args.light == "point":
        # Beside the sphere, so that it lights the relief at every angle and the sphere shadows the walls.
        doc["extensionsUsed"] = sorted(set(doc.get("extensionsUsed", [])) | {"KHR_lights_punctual"})
        doc["extensions"] = {"KHR_lights_punctual": {"lights": [
            {"name": "point", "type": "point", "color": [1.0, 0.662, 0.177], "intensity": 1.2}]}}
        doc["nodes"].append({"name": "point-light", "translation": [0.15, 0.5, 0.15],
                             "extensions": {"KHR_lights_punctual": {"light": 0}}})
        doc["scenes"][0]["nodes"] = list(range(len(doc["nodes"])))
    with open(os.path.join(args.out, bin_name), "wb") as f:
        f.write(bytes(g.buffer))
    path = os.path.join(args.out, name + ".gltf")
    with open(path, "w", encoding="ascii", newline="\n") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print("%s: %d triangles, %d bytes of buffer" % (path, 32 + len(indices) // 3, len(g.buffer)))


if __name__ == "__main__":
    main()
