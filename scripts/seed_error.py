#!/usr/bin/env python3
"""Noise figures of Monte Carlo renders, from two or more PFM images of one scene (docs/benchmarks.md, "Distance
sampling toward the lights"): each image's mean and brightest pixel, and the 4x4-block relMSE between the first two
(relMSE = mean((I - R)^2 / (R^2 + 0.01)) over pixels and channels of the block averages, docs/theory.md §10: two seeds'
images compared with each other measure the estimator's noise at the scale of features, fireflies included).

Usage: python3 scripts/seed_error.py A.pfm B.pfm [more.pfm ...] [--block 4] [--seconds S]
With --seconds (the wall time of one of the renders) it also prints seconds x block relMSE, the error per second figure.
Standard library only.
"""

import argparse
import struct


def read_pfm(path):
    """Returns (width, height, rows) with rows[y][x] = (r, g, b), y from the top."""
    with open(path, "rb") as f:
        kind = f.readline().strip()
        if kind not in (b"PF", b"Pf"):
            raise SystemExit("%s: not a PFM file" % path)
        channels = 3 if kind == b"PF" else 1
        width, height = (int(v) for v in f.readline().split())
        scale = float(f.readline())
        endian = "<" if scale < 0 else ">"
        data = struct.unpack(endian + "%df" % (width * height * channels), f.read(4 * width * height * channels))
    rows = []
    for y in range(height):
        row = []
        for x in range(width):
            i = (y * width + x) * channels
            row.append(tuple(data[i:i + 3]) if channels == 3 else (data[i],) * 3)
        rows.append(row)
    rows.reverse()  # PFM stores the bottom row first
    return width, height, rows


def block_average(width, height, rows, block):
    out = []
    for by in range(0, height, block):
        for bx in range(0, width, block):
            s, n = [0.0, 0.0, 0.0], 0
            for y in range(by, min(by + block, height)):
                for x in range(bx, min(bx + block, width)):
                    for c in range(3):
                        s[c] += rows[y][x][c]
                    n += 1
            out.append([v / n for v in s])
    return out


def rel_mse(image, reference):
    total = 0.0
    for p, r in zip(image, reference):
        for c in range(3):
            total += (p[c] - r[c]) ** 2 / (r[c] ** 2 + 0.01)
    return total / (3 * len(image))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("images", nargs="+")
    parser.add_argument("--block", type=int, default=4)
    parser.add_argument("--seconds", type=float)
    args = parser.parse_args()
    loaded = [read_pfm(p) for p in args.images]
    for path, (w, h, rows) in zip(args.images, loaded):
        pixels = [p for row in rows for p in row]
        mean = [sum(p[c] for p in pixels) / len(pixels) for c in range(3)]
        brightest = max(max(p) for p in pixels)
        print("%s: %dx%d mean %.6f %.6f %.6f (all %.6f) max pixel %.4f" %
              (path, w, h, mean[0], mean[1], mean[2], sum(mean) / 3, brightest))
    if len(loaded) >= 2:
        (w, h, a), (w2, h2, b) = loaded[0], loaded[1]
        if (w, h) != (w2, h2):
            raise SystemExit("the images differ in size")
        # Symmetric: each image as the other's reference, averaged.
        ba, bb = block_average(w, h, a, args.block), block_average(w, h, b, args.block)
        value = 0.5 * (rel_mse(ba, bb) + rel_mse(bb, ba))
        print("%dx%d-block relMSE between the first two: %.6f" % (args.block, args.block, value))
        if args.seconds is not None:
            print("seconds x block relMSE: %.6f" % (args.seconds * value))


if __name__ == "__main__":
    main()
