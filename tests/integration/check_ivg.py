#!/usr/bin/env python3
"""Reads an .ivg file (docs/irradiance-vector-grid.md) independently of the C++ reader and checks it:
check_ivg.py FILE MIN_NONZERO_FRACTION -> prints the cells and exits 1 when the header or the data
are inconsistent, a value is not finite, or too few values are non-zero."""
import math
import struct
import sys


def read_ivg(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    if header[0] != "RADIANCE_IVG 1":
        raise ValueError("not an .ivg file: " + header[0])
    fields = {}
    for line in header[1:]:
        key, _, rest = line.partition(" ")
        fields[key] = rest
    cells = [int(x) for x in fields["cells"].split()]
    count = (cells[0] + 1) * (cells[1] + 1) * (cells[2] + 1) * 54
    body = data[end:]
    if len(body) != 4 * count:
        raise ValueError(f"{len(body)} data bytes, {4 * count} expected for cells {cells}")
    values = struct.unpack(f"<{count}f", body)
    return cells, fields, values


def main():
    cells, fields, values = read_ivg(sys.argv[1])
    minimum = float(sys.argv[2])
    if not all(math.isfinite(v) for v in values):
        print("non-finite values")
        return 1
    nonzero = sum(1 for v in values if v != 0.0) / len(values)
    print(f"cells {cells[0]} {cells[1]} {cells[2]}, bounces {fields.get('bounces')}, rays {fields.get('rays')}, "
          f"{100 * nonzero:.1f} % non-zero")
    return 0 if nonzero >= minimum else 1


if __name__ == "__main__":
    sys.exit(main())
