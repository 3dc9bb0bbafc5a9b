"""Small PNG thumbnails of a mesh with numpy only (no matplotlib, no OpenGL): the batch report's
picture of each object.

    rgba = render_thumbnail(positions, faces, colors, size=160)   # (size, size, 4) uint8
    write_png('thumb.png', rgba)                                   # atomic: temporary, then rename

The mesh is seen orthographically from a fixed three-quarter view (so every object of a collection
is drawn the same way), its faces sampled on a barycentric grid fine enough to leave no holes,
splatted with a depth test, coloured by the interpolated vertex colours (grey without) and shaded by
the faces' facing ratio so the shape reads. Points without faces are splatted as they are.
"""

import os
import struct
import tempfile
import zlib

import numpy as np

# A three-quarter view: 30 degrees about the vertical, then 20 degrees down.
_YAW, _PITCH = np.radians(30.0), np.radians(-20.0)
# The most samples one thumbnail costs (memory and time stay small for any mesh size).
_MAX_SAMPLES = 600_000


def _view_rotation():
    cy, sy, cp, sp = np.cos(_YAW), np.sin(_YAW), np.cos(_PITCH), np.sin(_PITCH)
    yaw = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    pitch = np.array([[1, 0, 0], [0, cp, -sp], [0, sp, cp]])
    return pitch @ yaw


def _to_pixels(positions, size, margin):
    """View-space positions scaled so the bounding square fills the image minus a margin."""
    view = positions @ _view_rotation().T
    lo, hi = view[:, :2].min(0), view[:, :2].max(0)
    extent = max(float((hi - lo).max()), 1e-12)
    scale = (size - 2 * margin - 1) / extent
    centre = (lo + hi) / 2
    px = (view[:, 0] - centre[0]) * scale + (size - 1) / 2
    py = (size - 1) / 2 - (view[:, 1] - centre[1]) * scale  # image rows grow downward
    return np.stack([px, py], 1), view


def _face_samples(pixels, view, faces, colors):
    """Barycentric grid samples of every face: pixel position, depth, colour and shading."""
    corners = pixels[faces]
    edges = np.linalg.norm(corners - np.roll(corners, 1, axis=1), axis=2).max(1)
    # Samples closer than a pixel along the longest edge (1.5 per pixel: no gaps between rounded samples).
    wanted = int(np.clip(np.ceil(1.5 * edges.max() if len(edges) else 1), 1, 512))
    budget = int(np.floor(np.sqrt(2 * _MAX_SAMPLES / max(len(faces), 1))))
    steps = min(wanted, budget)
    if steps < 2:  # faces of about a pixel or less (dense scans): their centres fill the picture
        bary = np.full((1, 3), 1.0 / 3.0)
    else:
        i, j = np.meshgrid(np.arange(steps + 1), np.arange(steps + 1), indexing="ij")
        keep = (i + j) <= steps
        bary = np.stack([i[keep], j[keep], steps - i[keep] - j[keep]], 1) / steps  # (S, 3)
    xy = np.matmul(bary, corners).reshape(-1, 2)               # (F, S, 2): matmul broadcasts over faces
    z = (view[faces, 2] @ bary.T).reshape(-1)
    rgb = np.matmul(bary, colors[faces]).reshape(-1, 3)
    shade = np.repeat(_facing(view, faces), len(bary))
    return xy, z, rgb * shade[:, None]


def _facing(view, faces):
    """|cos| between each face's normal (in view space) and the view direction: 0.35..1."""
    p = view[faces]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    length = np.linalg.norm(n, axis=1)
    cos = np.abs(n[:, 2]) / np.maximum(length, 1e-30)
    return 0.35 + 0.65 * cos


def render_thumbnail(positions, faces=None, colors=None, size=160, margin=6):
    """An RGBA image (size x size, uint8) of the mesh; transparent where nothing is drawn."""
    positions = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    image = np.zeros((size, size, 4), dtype=np.uint8)
    if len(positions) == 0 or not np.isfinite(positions).all():
        return image
    colors = np.full((len(positions), 3), 0.7) if colors is None else np.asarray(colors, dtype=np.float64)[:, :3]
    pixels, view = _to_pixels(positions, size, margin)
    faces = np.zeros((0, 3), dtype=np.int64) if faces is None else np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if len(faces):
        xy, z, rgb = _face_samples(pixels, view, faces, colors)
    else:
        xy, z, rgb = pixels, view[:, 2], colors
    _splat(image, xy, z, rgb)
    return image


def _splat(image, xy, z, rgb):
    """Nearest sample wins: written from far to near, so the last write of a pixel is the nearest
    (the view looks down -z: larger z is nearer)."""
    size = image.shape[0]
    col = np.clip(np.rint(xy[:, 0]), 0, size - 1).astype(np.int64)
    row = np.clip(np.rint(xy[:, 1]), 0, size - 1).astype(np.int64)
    order = np.argsort(z, kind="stable")
    flat = row[order] * size + col[order]
    # The nearest sample of each pixel: the last occurrence in far-to-near order.
    last = len(flat) - 1 - np.unique(flat[::-1], return_index=True)[1]
    pick = order[last]
    image[row[pick], col[pick], :3] = np.clip(np.rint(rgb[pick] * 255), 0, 255).astype(np.uint8)
    image[row[pick], col[pick], 3] = 255


def png_bytes(rgba):
    """An 8-bit PNG of an (H, W, 4) RGBA or (H, W, 3) RGB array (filter 0 on every row, zlib level 6)."""
    rgba = np.ascontiguousarray(rgba, dtype=np.uint8)
    height, width, channels = rgba.shape
    if channels not in (3, 4):
        raise ValueError("a PNG image needs 3 (RGB) or 4 (RGBA) channels, not %d" % channels)
    raw = b"".join(b"\x00" + rgba[y].tobytes() for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 6 if channels == 4 else 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b"")


def write_png(path, rgba):
    """Writes the PNG (RGBA or RGB, see png_bytes) to a unique temporary beside `path`, then renames it over `path`."""
    write_atomically(path, png_bytes(rgba))


def write_atomically(path, data):
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, temporary = tempfile.mkstemp(prefix=".partial-", suffix=os.path.basename(path), dir=folder)
    try:
        os.fchmod(fd, 0o644)  # mkstemp makes 0600; the outputs are for whoever reads the folder
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise
