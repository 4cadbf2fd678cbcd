#!/usr/bin/env python3
"""Writes vehicle.obj: a small tracked-vehicle-like target made of boxes (tracks, hull, turret,
barrel), 3.2 m wide, 7.7 m long with the barrel, 2.3 m high; +Y is forward, the lowest point is
at z = 0, metres. Each box is closed with outward-facing counter-clockwise triangles.

Run: python3 data/targets/make_vehicle.py > data/targets/vehicle.obj
"""

BOXES = [  # (x0, x1, y0, y1, z0, z1)
    (-1.6, -1.0, -3.0, 3.0, 0.0, 0.8),  # left track
    (1.0, 1.6, -3.0, 3.0, 0.0, 0.8),  # right track
    (-1.4, 1.4, -3.2, 3.0, 0.5, 1.6),  # hull
    (-0.9, 0.9, -1.2, 1.0, 1.6, 2.3),  # turret
    (-0.08, 0.08, 1.0, 4.5, 1.85, 2.0),  # barrel
]

print("# Sylva example target: a box-model tracked vehicle (data/targets/make_vehicle.py)")
base = 0
for x0, x1, y0, y1, z0, z1 in BOXES:
    for z in (z0, z1):
        for y in (y0, y1):
            for x in (x0, x1):
                print(f"v {x:g} {y:g} {z:g}")
    # corners: index = 4*zi + 2*yi + xi (+1 for OBJ)
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    for a, b, c, d in quads:
        print(f"f {base + a + 1} {base + b + 1} {base + c + 1}")
        print(f"f {base + a + 1} {base + c + 1} {base + d + 1}")
    base += 8
