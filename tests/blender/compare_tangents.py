#!/usr/bin/env python3
"""Compares per-corner tangents "tx ty tz sign" of two files (ours, Blender's): every component
within the tolerance and every sign equal. Prints the largest difference; exit 1 on a mismatch.
Usage: compare_tangents.py OURS BLENDER NAME [TOLERANCE]"""
import sys


def read(path):
    with open(path) as f:
        return [tuple(float(x) for x in line.split()) for line in f if line.strip()]


ours, theirs, name = read(sys.argv[1]), read(sys.argv[2]), sys.argv[3]
tolerance = float(sys.argv[4]) if len(sys.argv) > 4 else 1e-4
if len(ours) != len(theirs) or not ours:
    sys.exit("FAIL %s: %d corners from us, %d from Blender" % (name, len(ours), len(theirs)))
worst, worst_corner, sign_errors = 0.0, -1, []
for corner, (a, b) in enumerate(zip(ours, theirs)):
    d = max(abs(a[k] - b[k]) for k in range(3))
    if d > worst:
        worst, worst_corner = d, corner
    if a[3] != b[3]:
        sign_errors.append(corner)
print("%s: %d corners, largest component difference %.3g (corner %d), %d sign differences"
      % (name, len(ours), worst, worst_corner, len(sign_errors)))
if worst > tolerance or sign_errors:
    if worst > tolerance:
        print("  corner %d: ours %s, Blender %s" % (worst_corner, ours[worst_corner], theirs[worst_corner]))
    for c in sign_errors[:5]:
        print("  sign differs at corner %d: ours %s, Blender %s" % (c, ours[c], theirs[c]))
    sys.exit("FAIL %s: tangents differ from Blender's beyond %g" % (name, tolerance))
