#!/usr/bin/env python3
"""Writes the forest example rasters: a 16-bit elevation map (PNG, one channel) and a 16-bit
vegetation feature map (Weber & Penn §6: bits 0-13 tree species, bits 14-15 grass type 1-3)
registered over it. The shipped small pair in data/examples/rasters/ is this script's default
output; larger areas (say --size 2000 for 400 ha) are generated, not shipped.

Usage: make_forest_rasters.py [--size METRES] [--dem-pixel M] [--feature-pixel M] [--seed S] [OUT_DIR]
Files: OUT_DIR/hills_dem.png (metres x 100: vertical_scale = 0.01) and OUT_DIR/hills_features.png.
Standard library only (zlib + struct), so it runs anywhere Python 3 does.
"""
import argparse
import math
import os
import struct
import zlib


def write_png16(path, width, height, values):
    """One-channel 16-bit PNG, rows top first (north first, as rasters are stored)."""
    raw = bytearray()
    for y in range(height):
        raw.append(0)  # filter: none
        row = values[y * width:(y + 1) * width]
        raw += struct.pack(">%dH" % width, *row)

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 16, 0, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(bytes(raw), 9))
    png += chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def lattice(seed, x, y):
    h = (x * 374761393 + y * 668265263 + seed * 2147483647) & 0xFFFFFFFF
    h = ((h ^ (h >> 13)) * 1274126177) & 0xFFFFFFFF
    return ((h ^ (h >> 16)) & 0xFFFF) / 32767.5 - 1.0


def value_noise(seed, x, y):
    ix, iy = math.floor(x), math.floor(y)
    fx, fy = x - ix, y - iy
    u = fx * fx * fx * (fx * (fx * 6 - 15) + 10)
    v = fy * fy * fy * (fy * (fy * 6 - 15) + 10)
    a = lattice(seed, ix, iy) + u * (lattice(seed, ix + 1, iy) - lattice(seed, ix, iy))
    b = lattice(seed, ix, iy + 1) + u * (lattice(seed, ix + 1, iy + 1) - lattice(seed, ix, iy + 1))
    return a + v * (b - a)


def fbm(seed, x, y, octaves=5):
    return sum(0.5 ** o * value_noise(seed + 17 * o, x * 2 ** o, y * 2 ** o) for o in range(octaves))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--size", type=float, default=200.0, help="side of the square area, m (default 200: 4 ha)")
    ap.add_argument("--dem-pixel", type=float, default=1.0, help="elevation pixel, m (default 1)")
    ap.add_argument("--feature-pixel", type=float, default=2.0, help="feature-map pixel, m (default 2)")
    ap.add_argument("--relief", type=float, default=12.0, help="height range, m (default 12)")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("out_dir", nargs="?", default=os.path.join(os.path.dirname(__file__), "..", "data", "examples",
                                                              "rasters"))
    a = ap.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)

    # Elevation: fBm hills of 150 m wavelength, heights in cm (vertical_scale = 0.01).
    n = int(round(a.size / a.dem_pixel))
    z = [fbm(a.seed, (x + 0.5) * a.dem_pixel / 150.0, (y + 0.5) * a.dem_pixel / 150.0)
         for y in range(n) for x in range(n)]
    lo, hi = min(z), max(z)
    dem = [int(round((v - lo) / (hi - lo) * a.relief * 100.0)) for v in z]
    write_png16(os.path.join(a.out_dir, "hills_dem.png"), n, n, dem)

    # Features: four species stands (bits 0-3, the noise field that is largest), clearings, a
    # north-south track of short grass (type 3) through the middle, meadow (1) and dry grass (2).
    m = int(round(a.size / a.feature_pixel))
    features = []
    for y in range(m):
        for x in range(m):
            px, py = (x + 0.5) * a.feature_pixel, (y + 0.5) * a.feature_pixel
            bits = 0
            track = abs(px - 0.5 * a.size - 6.0 * math.sin(py / 25.0)) < 3.0
            cover = value_noise(a.seed + 101, px / 45.0, py / 45.0)
            if not track and cover < 0.35:
                stands = [value_noise(a.seed + 200 + s, px / 40.0, py / 40.0) for s in range(4)]
                bits |= 1 << stands.index(max(stands))
            if track:
                grass = 3
            else:
                grass = 1 if value_noise(a.seed + 300, px / 30.0, py / 30.0) > -0.2 else 2
            features.append(bits | grass << 14)
    write_png16(os.path.join(a.out_dir, "hills_features.png"), m, m, features)
    print("wrote %dx%d elevation and %dx%d feature map over %g m in %s" % (n, n, m, m, a.size, a.out_dir))


if __name__ == "__main__":
    main()
