#!/usr/bin/python3
"""Writes the bundled smoke's density grid, assets/scenes/cornell-smoke.vdb: a procedural rising plume through
OpenVDB's Python module (Debian's python3-openvdb, hence /usr/bin/python3). The scene that places it,
assets/scenes/cornell-smoke.gltf, comes from scripts/make_scenes.py. The same grid every run (the
file's header holds a random UUID, so its bytes differ).

The plume: a column rising from a source near the floor, its radius growing with height (a buoyant plume widens
about linearly), its core density falling with height as it mixes, a slow swirl and two layers of smooth
pseudo-turbulence (sums of sines) so that its density varies at several scales, and a soft top."""
import argparse
import math
import os

import numpy as np
import pyopenvdb as vdb

# Voxels along x, y (up), z; the voxel edge in metres (the grid's own transform: the glTF node places it).
SIZE = (32, 48, 32)
VOXEL = 0.01


def plume(size):
    nx, ny, nz = size
    x = (np.arange(nx) + 0.5) / nx - 0.5
    y = (np.arange(ny) + 0.5) / ny
    z = (np.arange(nz) + 0.5) / nz - 0.5
    X, Y, Z = np.meshgrid(x, y, z, indexing="ij")
    # The column's axis sways with height; its radius grows from 0.10 to 0.42 of the grid's width.
    cx = 0.08 * np.sin(2.0 * math.pi * (0.9 * Y + 0.1))
    cz = 0.06 * np.sin(2.0 * math.pi * (0.7 * Y + 0.35))
    radius = 0.10 + 0.32 * Y
    r2 = ((X - cx) ** 2 + (Z - cz) ** 2) / radius ** 2
    core = np.exp(-2.5 * r2) * (1.0 - 0.55 * Y)
    # Swirl and turbulence: a density that varies at three scales.
    angle = np.arctan2(Z - cz, X - cx)
    swirl = 0.5 + 0.5 * np.sin(3.0 * angle + 9.0 * Y)
    turb = (0.55 + 0.25 * np.sin(17.0 * X + 11.0 * Y + 3.0) * np.sin(13.0 * Z - 7.0 * Y + 1.0)
            + 0.20 * np.sin(37.0 * Y + 23.0 * X) * np.sin(31.0 * Z + 5.0))
    density = core * (0.6 + 0.4 * swirl) * np.clip(turb, 0.0, None)
    # A soft top and a source that starts a little above the floor.
    density *= np.clip((1.0 - Y) / 0.15, 0.0, 1.0) * np.clip((Y - 0.01) / 0.06, 0.0, 1.0)
    density[density < 1e-3] = 0.0
    return np.ascontiguousarray(density / density.max(), dtype=np.float32)


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(root, "assets", "scenes", "cornell-smoke.vdb"))
    args = parser.parse_args()
    grid = vdb.FloatGrid()
    grid.copyFromArray(plume(SIZE), ijk=(0, 0, 0), tolerance=0.0)
    grid.transform = vdb.createLinearTransform(voxelSize=VOXEL)
    grid.gridClass = vdb.GridClass.FOG_VOLUME
    grid.name = "density"
    vdb.write(args.out, grids=[grid])
    print("%s: %d active voxels, %s voxels of %g m" % (args.out, grid.activeVoxelCount(), "x".join(map(str, SIZE)),
                                                      VOXEL))


if __name__ == "__main__":
    main()
