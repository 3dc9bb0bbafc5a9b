"""An independent, minimal PNG reader (pure Python 3: `struct` and `zlib` only) for the
integration checks: non-interlaced greyscale-free PNGs, RGB or RGBA, 8 or 16 bits per sample.
It shares no code with the C++ side (stb_image / libpng).

    png = read_png(path)           # raises PngError with the file name on anything else
    png.width, png.height, png.depth, png.channels
    png.sample(x, y, k)            # channel k of pixel (x, y), row 0 at the top, 0..255 or 0..65535
"""
import struct
import zlib


class PngError(Exception):
    pass


class Png:
    def __init__(self, width, height, depth, channels, rows):
        self.width, self.height, self.depth, self.channels = width, height, depth, channels
        self.rows = rows  # unfiltered bytes, one bytes object per row

    def sample(self, x, y, k):
        if self.depth == 16:
            return struct.unpack_from(">H", self.rows[y], 2 * (x * self.channels + k))[0]
        return self.rows[y][x * self.channels + k]


def read_png(path):
    with open(path, "rb") as f:
        blob = f.read()
    if blob[:8] != b"\x89PNG\r\n\x1a\n":
        raise PngError(f"{path} is not a PNG file")
    pos, idat, header = 8, b"", None
    while pos < len(blob):
        length, kind = struct.unpack(">I4s", blob[pos:pos + 8])
        data = blob[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", data)
        elif kind == b"IDAT":
            idat += data
        elif kind == b"IEND":
            break
    if header is None:
        raise PngError(f"{path}: no IHDR chunk")
    width, height, depth, colour, _, _, interlace = header
    if depth not in (8, 16) or colour not in (2, 6) or interlace != 0:
        raise PngError(f"{path}: unsupported PNG (depth {depth}, colour type {colour}, interlace {interlace})")
    channels = 3 if colour == 2 else 4
    bpp = channels * depth // 8  # bytes per pixel: the filters' left neighbour distance
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows, previous, pos = [], bytearray(stride), 0
    for _ in range(height):
        kind = raw[pos]
        line = bytearray(raw[pos + 1:pos + 1 + stride])
        pos += 1 + stride
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = previous[i]
            c = previous[i - bpp] if i >= bpp else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        previous = line
    return Png(width, height, depth, channels, rows)
