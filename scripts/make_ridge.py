#!/usr/bin/python3
"""Writes the height map of the ridge scene (launch/scenes/ridge.yaml): a ridge with a rounded
crest (a circular cap of radius 6 mm, 10 mm high, its sides cut vertical 5 mm from the crest
line, 7.3 mm high there) whose crest line curves in an S, x = A sin(pi y / L) for y in [-L, L]
(A = 5 mm, L = 22 mm), ends rounded; as a 16-bit grayscale PNG (0.5 mm cells, heights
max_height_m = 0.012 m full scale). Heights are above the map's centre, 0.5 mm under the
floor (center_m z = -0.0005 in the scene), so the map's flat part lies under the floor plane
and only the ridge stands out of it. Prints the crest line's points for the scene's task and
the chords a virtual subject remembers as its route. Standard library only.

  scripts/make_ridge.py [OUT.png]      (default: launch/scenes/ridge_heights.png)
"""
import math
import os
import struct
import sys
import zlib

A_M, L_M = 0.005, 0.022            # the S: amplitude and half length
TOP_M, CAP_RADIUS_M, HALF_WIDTH_M = 0.010, 0.006, 0.005
CELL_M, COLS, ROWS = 0.0005, 61, 117   # x in [-15, 15] mm, y in [-29, 29] mm
MAX_HEIGHT_M = 0.012
BELOW_FLOOR_M = 0.0005   # the map's heights start this far under the floor


def crest(samples):
    return [(A_M * math.sin(math.pi * y / L_M), y) for y in (-L_M + 2 * L_M * i / (samples - 1) for i in range(samples))]


def distance_to(line, x, y):
    best = float("inf")
    for (ax, ay), (bx, by) in zip(line, line[1:]):
        dx, dy = bx - ax, by - ay
        t = max(0.0, min(1.0, ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy)))
        best = min(best, math.hypot(x - ax - t * dx, y - ay - t * dy))
    return best


def height(d):
    """above the map's centre (BELOW_FLOOR_M under the floor)"""
    if d >= HALF_WIDTH_M:
        return 0.0
    return BELOW_FLOOR_M + TOP_M - CAP_RADIUS_M + math.sqrt(CAP_RADIUS_M ** 2 - d * d)


def png16(path, rows):
    raw = b"".join(b"\x00" + struct.pack(">%dH" % len(r), *r) for r in rows)
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", len(rows[0]), len(rows), 16, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "launch", "scenes", "ridge_heights.png")
    out = os.path.normpath(out)
    fine = crest(401)
    rows = []
    for r in range(ROWS):  # row 0 at +y, column 0 at -x (docs/scenes-and-models.md, "Objects")
        y = (ROWS - 1) / 2 * CELL_M - r * CELL_M
        row = []
        for c in range(COLS):
            x = -(COLS - 1) / 2 * CELL_M + c * CELL_M
            row.append(round(height(distance_to(fine, x, y)) / MAX_HEIGHT_M * 65535))
        rows.append(row)
    png16(out, rows)
    print("wrote", out)
    print("task points_m:", [[round(x, 5), round(y, 5)] for x, y in crest(23)])
    knots = crest(5)
    chords = [(math.degrees(math.atan2(bx - ax, by - ay)), math.hypot(bx - ax, by - ay)) for (ax, ay), (bx, by) in zip(knots, knots[1:])]
    print("route chords (heading deg, length m):", [(round(h, 1), round(l, 5)) for h, l in chords])


if __name__ == "__main__":
    main()
