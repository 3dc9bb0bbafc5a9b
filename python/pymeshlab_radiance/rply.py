"""Read and write the project's Radiance PLY files (``.rply``) with numpy alone.

The format is specified in ``docs/radiance-ply-format.md`` (version 1): a binary little-endian PLY 1.0
file whose vertices carry the radiance functions (RF) of Vanhoey et al. 2015 -- hemispherical
polynomials ``PB0``..``PB8`` in a per-vertex tangent frame, or real spherical harmonics ``SH0``..``SH10``
in the global frame -- as float properties ``rf_<r|g|b>_<k>``, the frame tangent as ``rf_tx rf_ty
rf_tz``, optional extra per-vertex float blocks (e.g. the PRT transfer vectors of Sloan et al. 2002 as
block ``prt``), and their meaning in header ``comment`` lines.

This module is independent of the C++ implementation (``common/io/radiance_ply.cpp``) but follows the
same rules:

* :func:`read_rply` follows the section "Reader" of the specification: properties looked up by name in
  any order, unknown scalar vertex properties and unknown scalar-only elements skipped, type aliases,
  colours without ``alpha``, extra face properties, ``vertex_index``, ``\\r\\n`` line ends, ``obj_info``
  lines.  The whole layout is checked against the file size before anything is allocated, then every
  element is read with one ``readinto`` and decoded with strided numpy views (a 1M-vertex PB4 file
  reads in a fraction of a second).  Everything the specification's refusal table refuses raises
  :class:`RadianceFileError` with ``cannot load '<path>': <what is wrong>; <how to fix>``.
* :func:`write_rply` follows the section "Writer": it validates the whole mesh first, then writes the
  very bytes the C++ writer writes for the same data (same header lines in the same order, block
  metadata sorted by key, packed little-endian records) to a temporary file ``<path>.part-...`` in the
  same folder, ``fsync``s it and renames it over ``path``.  On any failure the temporary file is
  removed and an existing file at ``path`` is untouched.

Example::

    from pymeshlab_radiance import rply
    mesh = rply.read_rply("bunny.rply")
    mesh.basis, mesh.coefficients.shape      # ('PB4', (37706, 3, 15))
    rf_g_3 = mesh.coefficients[:, 1, 3]      # property rf_g_3 of every vertex
    rply.write_rply("copy.rply", mesh)       # byte-identical to a file written by the C++ side
"""

from __future__ import annotations

import itertools
import os
import re
import time
from dataclasses import dataclass, field
from typing import Dict, List, NoReturn, Optional, Tuple, Union

import numpy as np

# A file name as the functions accept it: a string or a path-like object (pathlib.Path).
PathLike = Union[str, "os.PathLike[str]"]

__all__ = [
    "FORMAT_VERSION",
    "RadianceFileError",
    "Block",
    "RadianceMesh",
    "read_rply",
    "write_rply",
    "validate_mesh",
    "parse_basis",
    "basis_coefficient_count",
]

#: ``comment radiance_format_version`` written and the highest version read (specification, "Versioning").
FORMAT_VERSION = 1

# Limits of the specification (section "Limits").
_MAX_HEADER_BYTES = 1 << 20
_MAX_BLOCK_WIDTH = 65536
_MAX_ELEMENT_COUNT = 0xFFFFFFFF          # vertex and face counts on read
_MAX_WRITTEN_VERTEX_COUNT = 0x80000000   # indices are written as int
_MAX_PB_DEGREE = 8
_MAX_SH_DEGREE = 10
_UNIT_NORMAL_TOLERANCE = 1e-3            # | |n|^2 - 1 | bound of RadianceField::validate
_CHANNELS = ("r", "g", "b")

_CONVERT_HINT = ("our writer produces binary little endian PLY; convert the file, e.g. open it in MeshLab and "
                 "export it again as PLY with the 'Binary encoding' box checked")


class RadianceFileError(ValueError):
    """A file that cannot be read, or a mesh that cannot be written; the message says what is wrong and
    how to fix it (specification, "Refused with RadianceFileError")."""


@dataclass(eq=False)
class Block:
    """An extra per-vertex float array (specification, "comment block <prefix> width <n>"): stored as
    the vertex properties ``<prefix>_0`` .. ``<prefix>_<w-1>``; ``values[v, i]`` is ``<prefix>_<i>`` of
    vertex ``v``.  ``meta`` holds the ``block_meta`` entries (keys without whitespace, values without
    control characters; written sorted by key)."""

    values: np.ndarray
    meta: Dict[str, str] = field(default_factory=dict)

    @property
    def width(self) -> int:
        """Floats per vertex."""
        return int(self.values.shape[1]) if getattr(self.values, "ndim", 0) == 2 else 0


def _no_faces() -> np.ndarray:
    return np.zeros((0, 3), dtype=np.int32)


@dataclass(eq=False)
class RadianceMesh:
    """A triangle mesh with optional per-vertex radiance functions, as numpy arrays (the in-memory
    counterpart of ``common/io/radiance_mesh.h``; specification, "Vertex properties").

    * ``positions`` (N, 3) float32 -- ``x y z``.
    * ``faces`` (F, 3) int32 -- triangles, 0-based vertex indices.
    * ``normals`` (N, 3) float32 or None -- ``nx ny nz``; with radiance they are the RF frame normals
      (required, unit length).
    * ``colors`` (N, 4) uint8 or None -- ``red green blue alpha``.
    * ``quality`` (N,) float32 or None -- ``quality`` (user data: NaN allowed).
    * ``basis`` -- ``'PB0'``..``'PB8'``, ``'SH0'``..``'SH10'``, or None without radiance.
    * ``reflected`` -- the coefficients encode the reflected RF L~(w) = L(R_n w) (Vanhoey et al. 2015).
    * ``tangents`` (N, 3) float32 or None -- frame tangent ``rf_tx rf_ty rf_tz`` (bitangent = n x t).
    * ``coefficients`` (N, 3, K) float32 or None -- channel-major as in the file:
      ``coefficients[v, c, k]`` is ``rf_<c>_<k>`` of vertex ``v`` (c = 0, 1, 2 for r, g, b).
    * ``blocks`` -- prefix -> :class:`Block`, in file order.
    * ``skipped`` -- filled by :func:`read_rply` only (the writer ignores it): one sentence per piece of
      the file that was not loaded (unknown vertex properties, unknown elements, extra face
      properties), as ``RadianceMesh::skippedOnRead`` of the C++ reader.
    """

    positions: np.ndarray
    faces: np.ndarray = field(default_factory=_no_faces)
    normals: Optional[np.ndarray] = None
    colors: Optional[np.ndarray] = None
    quality: Optional[np.ndarray] = None
    basis: Optional[str] = None
    reflected: bool = False
    tangents: Optional[np.ndarray] = None
    coefficients: Optional[np.ndarray] = None
    blocks: Dict[str, Block] = field(default_factory=dict)
    skipped: List[str] = field(default_factory=list)

    @property
    def vertex_count(self) -> int:
        """N, the number of vertices."""
        return int(np.shape(self.positions)[0])

    @property
    def face_count(self) -> int:
        """F, the number of triangles."""
        return 0 if self.faces is None else int(np.shape(self.faces)[0])

    @property
    def coefficient_count(self) -> int:
        """K, the coefficients per colour channel of ``basis`` ((d+1)(d+2)/2 for PB(d), (d+1)^2 for
        SH(d)); 0 without radiance.  Each vertex stores 3 K coefficients."""
        return 0 if self.basis is None else basis_coefficient_count(self.basis)


# ---------------------------------------------------------------------------------------------------
# Bases


def parse_basis(text: str) -> Optional[Tuple[str, int]]:
    """``'PB4'`` -> ``('PB', 4)``; case-insensitive like ``BasisSpec::parse``; None when malformed or the
    degree is out of range (PB 0..8, SH 0..10)."""
    if not isinstance(text, str) or not 3 <= len(text) <= 4:
        return None
    kind = text[:2].upper()
    digits = text[2:]
    if kind not in ("PB", "SH") or not all(c in "0123456789" for c in digits):
        return None
    degree = int(digits)
    if degree > (_MAX_PB_DEGREE if kind == "PB" else _MAX_SH_DEGREE):
        return None
    return kind, degree


def basis_coefficient_count(basis: str) -> int:
    """K, the coefficients per channel of a basis name: (d+1)(d+2)/2 for PB(d), (d+1)^2 for SH(d)."""
    parsed = parse_basis(basis)
    if parsed is None:
        raise RadianceFileError(f"unknown radiance basis {_shown(str(basis))} (supported: PB0..PB{_MAX_PB_DEGREE}, "
                                f"SH0..SH{_MAX_SH_DEGREE})")
    kind, d = parsed
    return (d + 1) * (d + 2) // 2 if kind == "PB" else (d + 1) * (d + 1)


def _basis_name(basis: str) -> str:
    kind, d = parse_basis(basis)
    return f"{kind}{d}"


# ---------------------------------------------------------------------------------------------------
# Small helpers


def _fail(message: str) -> NoReturn:
    raise RadianceFileError(message)


def _shown(text: str) -> str:
    """A header token as it may appear in a message: quoted, non-printable bytes escaped, bounded."""
    raw = text.encode("utf-8", "surrogateescape")
    out = []
    for b in raw[:48]:
        out.append(chr(b) if 0x20 <= b < 0x7F else f"\\x{b:02x}")
    return "'" + "".join(out) + ("..." if len(raw) > 48 else "") + "'"


def _parse_unsigned(s: str) -> Optional[int]:
    """Decimal digits only (no sign, no blanks), at most 2^64-1."""
    if not s or len(s) > 20 or not all(c in "0123456789" for c in s):
        return None
    value = int(s)
    return value if value <= 0xFFFFFFFFFFFFFFFF else None


_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,63}\Z")


def _is_identifier(s: str) -> bool:
    return bool(_IDENTIFIER.match(s))


def _is_reserved_prefix(s: str) -> bool:
    return s == "rf" or s.startswith("rf_")


def _utf8(s: str) -> bytes:
    return s.encode("utf-8", "surrogateescape")


def _is_metadata_key(s: str) -> bool:
    b = _utf8(s)
    return len(b) > 0 and all(u > 0x20 and u != 0x7F for u in b)


def _is_metadata_value(s: str) -> bool:
    return all(u >= 0x20 and u != 0x7F for u in _utf8(s))


def _tokenize(line: str) -> List[str]:
    return [t for t in re.split(r"[ \t]+", line) if t]


def _next_token(line: str, pos: int) -> Tuple[str, int]:
    """The next blank-separated token from pos and the position just after it (C++ ``nextToken``)."""
    n = len(line)
    while pos < n and line[pos] in " \t":
        pos += 1
    start = pos
    while pos < n and line[pos] not in " \t":
        pos += 1
    return line[start:pos], pos


# PLY type name -> (canonical name, numpy little-endian dtype)
_TYPES = {
    "char": ("char", "<i1"), "int8": ("char", "<i1"),
    "uchar": ("uchar", "<u1"), "uint8": ("uchar", "<u1"),
    "short": ("short", "<i2"), "int16": ("short", "<i2"),
    "ushort": ("ushort", "<u2"), "uint16": ("ushort", "<u2"),
    "int": ("int", "<i4"), "int32": ("int", "<i4"),
    "uint": ("uint", "<u4"), "uint32": ("uint", "<u4"),
    "float": ("float", "<f4"), "float32": ("float", "<f4"),
    "double": ("double", "<f8"), "float64": ("double", "<f8"),
}


class _Property:
    __slots__ = ("name", "is_list", "type", "count_type", "offset")

    def __init__(self, name, is_list, type_, count_type=None):
        self.name = name
        self.is_list = is_list
        self.type = type_            # canonical type name (list item type for lists)
        self.count_type = count_type  # list length type
        self.offset = 0              # byte offset within the record (scalars before any list)

    @property
    def size(self) -> int:
        return np.dtype(_TYPES[self.type][1]).itemsize

    @property
    def dtype(self) -> str:
        return _TYPES[self.type][1]


class _Element:
    def __init__(self, name: str, count: int):
        self.name = name
        self.count = count
        self.properties: List[_Property] = []
        self.by_name: Dict[str, int] = {}
        self.has_list = False
        self.scalar_bytes = 0

    def find(self, name: str) -> Optional[_Property]:
        i = self.by_name.get(name)
        return None if i is None else self.properties[i]


class _Comment:
    __slots__ = ("tokens", "line", "number")

    def __init__(self, tokens, line, number):
        self.tokens = tokens
        self.line = line
        self.number = number


# ---------------------------------------------------------------------------------------------------
# Header


def _parse_header(head: bytes, whole_file: bool):
    """Elements, comments and the data offset of the header in ``head`` (the first bytes of the file)."""
    if not head:
        _fail("not a PLY file: the file is empty")
    if not (head.startswith(b"ply\n") or head.startswith(b"ply\r\n")):
        _fail("not a PLY file: it does not start with the line 'ply'")
    elements: List[_Element] = []
    comments: List[_Comment] = []
    format_seen = ended = False
    pos = 0
    number = 0
    while pos < len(head):
        nl = head.find(b"\n", pos)
        if nl < 0:
            break
        raw = head[pos:nl]
        pos = nl + 1
        number += 1
        if raw.endswith(b"\r"):
            raw = raw[:-1]
        if number == 1:
            continue  # "ply"
        line = raw.decode("utf-8", "surrogateescape")
        t = _tokenize(line)
        if not t:
            continue
        keyword = t[0]
        where = f"header line {number}: "
        if keyword == "end_header":
            if len(t) != 1:
                _fail(where + "malformed end_header line")
            ended = True
            break
        if keyword == "comment":
            comments.append(_Comment(t, line, number))
            continue
        if keyword == "obj_info":
            continue
        if keyword == "format":
            if format_seen:
                _fail(where + "second format line")
            if elements:
                _fail(where + "the format line must come before the elements")
            if len(t) != 3:
                _fail(where + "malformed format line")
            if t[1] == "ascii":
                _fail("the PLY file is in ASCII format, which is not supported: " + _CONVERT_HINT)
            if t[1] == "binary_big_endian":
                _fail("the PLY file is binary big endian, which is not supported: " + _CONVERT_HINT)
            if t[1] != "binary_little_endian":
                _fail(where + f"unknown PLY format {_shown(t[1])}; " + _CONVERT_HINT)
            if t[2] != "1.0":
                _fail(where + f"unsupported PLY version {_shown(t[2])} (expected 1.0)")
            format_seen = True
            continue
        if keyword == "element":
            if not format_seen:
                _fail(where + "element before the format line")
            if len(t) != 3:
                _fail(where + "malformed element line")
            count = _parse_unsigned(t[2])
            if count is None:
                _fail(where + f"element {_shown(t[1])} has an invalid count {_shown(t[2])}")
            if any(e.name == t[1] for e in elements):
                _fail(where + f"element {_shown(t[1])} declared twice")
            elements.append(_Element(t[1], count))
            continue
        if keyword == "property":
            if not elements:
                _fail(where + "property before any element")
            element = elements[-1]
            if len(t) == 5 and t[1] == "list":
                if t[2] not in _TYPES or t[3] not in _TYPES:
                    _fail(where + f"unknown type in list property {_shown(t[4])}")
                count_type = _TYPES[t[2]][0]
                if count_type in ("float", "double"):
                    _fail(where + f"list property {_shown(t[4])} has a non-integer length type")
                p = _Property(t[4], True, _TYPES[t[3]][0], count_type)
            elif len(t) == 3 and t[1] != "list":
                if t[1] not in _TYPES:
                    _fail(where + f"unknown property type {_shown(t[1])}")
                p = _Property(t[2], False, _TYPES[t[1]][0])
            else:
                _fail(where + "malformed property line")
            if p.name in element.by_name:
                _fail(where + f"property {_shown(p.name)} of element {_shown(element.name)} declared twice")
            element.by_name[p.name] = len(element.properties)
            if p.is_list:
                element.has_list = True
            else:
                p.offset = element.scalar_bytes
                element.scalar_bytes += p.size
            element.properties.append(p)
            continue
        _fail(where + f"unknown header keyword {_shown(keyword)}; not a valid PLY header")
    if not ended:
        if whole_file:
            _fail("file truncated inside its header (no end_header line); the file was probably not "
                  "completely written")
        _fail("no end_header line in the first 1 MiB: not a PLY header this reader accepts")
    if not format_seen:
        _fail("the PLY header has no format line")
    return elements, comments, pos


class _RadianceHeader:
    def __init__(self):
        self.ours = False       # radiance_format_version present
        self.basis: Optional[str] = None
        self.reflected = False
        self.blocks: List[Tuple[str, int, Dict[str, str]]] = []


_RADIANCE_KEYS = ("radiance_basis", "radiance_reflected", "radiance_channels", "radiance_color_space",
                  "radiance_frame")


def _parse_radiance_comments(comments: List[_Comment]) -> _RadianceHeader:
    """The radiance comments (specification, "Comments" and its rules)."""
    r = _RadianceHeader()
    # The version first, so that a newer file gets the "newer version" message whatever else it holds.
    for c in comments:
        if len(c.tokens) < 2 or c.tokens[1] != "radiance_format_version":
            continue
        if r.ours:
            _fail("comment radiance_format_version appears twice")
        version = _parse_unsigned(c.tokens[2]) if len(c.tokens) == 3 else None
        if not version:
            _fail(f"header line {c.number}: malformed radiance_format_version comment")
        if version > FORMAT_VERSION:
            _fail(f"the file was written by a newer version of the radiance PLY format (version {c.tokens[2]}); "
                  f"this reader supports version {FORMAT_VERSION}: update the plugin (pymeshlab_radiance)")
        r.ours = True

    seen = set()
    first_key = None
    for c in comments:
        if len(c.tokens) < 2 or c.tokens[1] not in _RADIANCE_KEYS:
            continue
        key = c.tokens[1]
        if key in seen:
            _fail(f"comment {key} appears twice")
        seen.add(key)
        if first_key is None:
            first_key = key
        if len(c.tokens) != 3:
            _fail(f"header line {c.number}: malformed {key} comment")
        value = c.tokens[2]
        if key == "radiance_basis":
            if parse_basis(value) is None:
                kind = value[:2].upper()
                rest = value[2:]
                if kind in ("PB", "SH") and rest and all(ch in "0123456789" for ch in rest):
                    _fail(f"radiance basis {_shown(value)} has a degree out of range (PB degrees 0..{_MAX_PB_DEGREE}, "
                          f"SH degrees 0..{_MAX_SH_DEGREE})")
                _fail(f"unknown radiance basis {_shown(value)} in comment radiance_basis (supported: "
                      f"PB0..PB{_MAX_PB_DEGREE}, SH0..SH{_MAX_SH_DEGREE})")
            r.basis = _basis_name(value)
        elif key == "radiance_reflected":
            if value not in ("0", "1"):
                _fail(f"comment radiance_reflected must be 0 or 1, not {_shown(value)}")
            r.reflected = value == "1"
        elif key == "radiance_channels":
            if value != "rgb":
                _fail(f"unsupported radiance_channels {_shown(value)} (only rgb)")
        elif key == "radiance_color_space":
            if value != "linear":
                _fail(f"unsupported radiance_color_space {_shown(value)} (only linear)")
        elif key == "radiance_frame":
            if value != "tangent_normal":
                _fail(f"unsupported radiance_frame {_shown(value)} (only tangent_normal)")
    if first_key is not None and not r.ours:
        _fail(f"comment {first_key} without comment radiance_format_version; add the line "
              f"'comment radiance_format_version 1' to the header")
    if r.basis is not None and "radiance_reflected" not in seen:
        _fail("comment radiance_basis without comment radiance_reflected; add 'comment radiance_reflected 0' "
              "(or 1 when the coefficients encode the reflected function)")
    if r.basis is None and seen:
        _fail(f"comment {first_key} without comment radiance_basis")
    if not r.ours:
        return r  # "block" comments of foreign files are just comments

    for c in comments:
        t = c.tokens
        if len(t) < 2 or t[1] != "block":
            continue
        if len(t) != 5 or t[3] != "width":
            _fail(f"header line {c.number}: malformed block comment (expected 'comment block <prefix> width <n>')")
        if not _is_identifier(t[2]) or _is_reserved_prefix(t[2]):
            _fail(f"header line {c.number}: invalid block prefix {_shown(t[2])}")
        width = _parse_unsigned(t[4])
        if not width or width > _MAX_BLOCK_WIDTH:
            _fail(f"header line {c.number}: block {_shown(t[2])} has an invalid width {_shown(t[4])} "
                  f"(1..{_MAX_BLOCK_WIDTH})")
        if any(b[0] == t[2] for b in r.blocks):
            _fail(f"block {_shown(t[2])} declared twice")
        r.blocks.append((t[2], width, {}))
    for c in comments:
        if len(c.tokens) < 2 or c.tokens[1] != "block_meta":
            continue
        _, pos = _next_token(c.line, 0)  # comment
        _, pos = _next_token(c.line, pos)  # block_meta
        prefix, pos = _next_token(c.line, pos)
        key, pos = _next_token(c.line, pos)
        if not key:
            _fail(f"header line {c.number}: malformed block_meta comment (expected "
                  f"'comment block_meta <prefix> <key> <value>')")
        # The value is everything after the one blank that follows the key.
        value = c.line[pos + 1:] if pos < len(c.line) else ""
        block = next((b for b in r.blocks if b[0] == prefix), None)
        if block is None:
            _fail(f"header line {c.number}: block_meta for undeclared block {_shown(prefix)} "
                  f"(add 'comment block {prefix if _is_identifier(prefix) else '<prefix>'} width <n>')")
        # The writer refuses these, so accepting them would load a file that cannot be saved again.
        if not _is_metadata_key(key):
            _fail(f"header line {c.number}: block_meta key {_shown(key)} of block {_shown(prefix)} contains a control "
                  f"character; metadata keys are visible characters without blanks: rename the key in that header "
                  f"line")
        if not _is_metadata_value(value):
            _fail(f"header line {c.number}: the value of block_meta {_shown(key)} of block {_shown(prefix)} contains "
                  f"a control character ({_shown(value)}); metadata values are one line of printable text: replace "
                  f"the control characters (tabs, line breaks...) in that header line by spaces")
        if key in block[2]:
            _fail(f"block_meta {_shown(key)} of block {_shown(prefix)} appears twice")
        block[2][key] = value
    return r


# ---------------------------------------------------------------------------------------------------
# Layout


class _VertexLayout:
    def __init__(self):
        self.record = 0
        self.position = [-1] * 3
        self.normal = [-1] * 3
        self.color = [-1] * 4
        self.quality = -1
        self.tangent = [-1] * 3
        self.coefficients: List[int] = []   # c * K + k
        self.blocks: List[List[int]] = []
        self.unknown: List[str] = []         # names of the skipped properties


def _plan_vertices(vertex: _Element, rh: _RadianceHeader) -> _VertexLayout:
    layout = _VertexLayout()
    layout.record = vertex.scalar_bytes
    K = basis_coefficient_count(rh.basis) if rh.basis else 0

    block_total = sum(b[1] for b in rh.blocks)
    if block_total > len(vertex.properties):
        _fail(f"the block comments declare {block_total} vertex properties but the vertex element has only "
              f"{len(vertex.properties)} properties; block properties are missing")

    # name -> (slot, index, block)
    expected = {"x": ("p", 0), "y": ("p", 1), "z": ("p", 2), "nx": ("n", 0), "ny": ("n", 1), "nz": ("n", 2),
                "red": ("c", 0), "green": ("c", 1), "blue": ("c", 2), "alpha": ("c", 3), "quality": ("q", 0)}
    if rh.basis:
        expected.update({"rf_tx": ("t", 0), "rf_ty": ("t", 1), "rf_tz": ("t", 2)})
        for c in range(3):
            for k in range(K):
                expected[f"rf_{_CHANNELS[c]}_{k}"] = ("k", c * K + k)
        layout.coefficients = [-1] * (3 * K)
    for b, (prefix, width, _) in enumerate(rh.blocks):
        layout.blocks.append([-1] * width)
        for i in range(width):
            expected[f"{prefix}_{i}"] = ("b", i, b)
    block_prefixes = {b[0]: b for b in rh.blocks}

    for p in vertex.properties:
        if p.is_list:
            _fail(f"vertex property {_shown(p.name)} is a list: variable-size vertex records are not supported; "
                  f"remove that property (or re-save the mesh from MeshLab)")
        ref = expected.get(p.name)
        if ref is None:
            if p.name.startswith("rf_"):
                if not rh.basis:
                    _fail(f"vertex property {_shown(p.name)} looks like radiance data but the header has no "
                          f"radiance_basis comment; the comments were probably removed by another tool: add "
                          f"'comment radiance_format_version 1', 'comment radiance_basis <basis>' and "
                          f"'comment radiance_reflected 0|1'")
                _fail(f"vertex property {_shown(p.name)} does not belong to basis {rh.basis} (expected rf_tx rf_ty "
                      f"rf_tz and rf_r_0..rf_r_{K - 1}, rf_g_0..rf_g_{K - 1}, rf_b_0..rf_b_{K - 1}); the "
                      f"radiance_basis comment does not match the properties")
            us = p.name.rfind("_")
            if us >= 0:
                suffix = p.name[us + 1:]
                block = block_prefixes.get(p.name[:us])
                if block is not None and suffix and all(ch in "0123456789" for ch in suffix):
                    _fail(f"vertex property {_shown(p.name)} does not belong to block {_shown(block[0])} of width "
                          f"{block[1]} (expected {block[0]}_0..{block[0]}_{block[1] - 1})")
            layout.unknown.append(p.name)  # skipped by its size, and reported
            continue
        want = "uchar" if ref[0] == "c" else "float"
        if p.type != want:
            _fail(f"vertex property {_shown(p.name)} is {p.type} but must be {want}")
        slot, index = ref[0], ref[1]
        if slot == "p":
            layout.position[index] = p.offset
        elif slot == "n":
            layout.normal[index] = p.offset
        elif slot == "c":
            layout.color[index] = p.offset
        elif slot == "q":
            layout.quality = p.offset
        elif slot == "t":
            layout.tangent[index] = p.offset
        elif slot == "k":
            layout.coefficients[index] = p.offset
        else:
            layout.blocks[ref[2]][index] = p.offset

    for i, name in enumerate("xyz"):
        if layout.position[i] < 0:
            _fail(f"missing vertex property '{name}'; every vertex needs float x, y, z")
    normals = sum(o >= 0 for o in layout.normal)
    if normals not in (0, 3):
        for i, name in enumerate(("nx", "ny", "nz")):
            if layout.normal[i] < 0:
                _fail(f"missing vertex property '{name}'; normals need nx, ny and nz")
    colors = sum(o >= 0 for o in layout.color[:3])
    if colors not in (0, 3) or (colors == 0 and layout.color[3] >= 0):
        for i, name in enumerate(("red", "green", "blue")):
            if layout.color[i] < 0:
                _fail(f"missing vertex property '{name}'; colors need red, green, blue (and optionally alpha)")
    if rh.basis:
        if normals == 0:
            _fail("missing vertex property 'nx': radiance data needs the per-vertex normals (the frame normal "
                  "nx ny nz)")
        for i, name in enumerate(("rf_tx", "rf_ty", "rf_tz")):
            if layout.tangent[i] < 0:
                _fail(f"missing radiance frame tangent property '{name}'")
        for j, o in enumerate(layout.coefficients):
            if o < 0:
                _fail(f"missing radiance coefficient property 'rf_{_CHANNELS[j // K]}_{j % K}' (basis {rh.basis} "
                      f"needs rf_r_0..rf_r_{K - 1}, rf_g_0..rf_g_{K - 1}, rf_b_0..rf_b_{K - 1})")
    for b, (prefix, width, _) in enumerate(rh.blocks):
        for i in range(width):
            if layout.blocks[b][i] < 0:
                _fail(f"missing vertex property '{prefix}_{i}' of block {_shown(prefix)} (width {width})")
    return layout


def _plan_faces(face: _Element) -> Tuple[int, int]:
    """Index of the vertex index list property and the minimum (triangle) record size."""
    indices = face.find("vertex_indices") or face.find("vertex_index")
    if indices is None or not indices.is_list:
        _fail("the face element has no 'vertex_indices' list property")
    if indices.type not in ("int", "uint"):
        _fail(f"face property {_shown(indices.name)} has items of type {indices.type} but they must be int or uint")
    min_record = 0
    for p in face.properties:
        if not p.is_list:
            min_record += p.size
        else:
            min_record += np.dtype(_TYPES[p.count_type][1]).itemsize + (3 * p.size if p is indices else 0)
    return face.properties.index(indices), min_record


def _truncated(prefix: str, expected: int, found: int, what: str) -> str:
    return (f"file truncated: expected {prefix}{expected} bytes of {what}, found {found}; the file was probably "
            f"not completely written")


def _trailing(count: int) -> str:
    return (f"{count} {'byte' if count == 1 else 'bytes'} of unexpected data after the last element: the header "
            f"does not describe the data (wrong element count or property type?); this reader refuses trailing data")


# ---------------------------------------------------------------------------------------------------
# Decoding


def _read_exact(f, count: int, buf: Optional[np.ndarray] = None) -> np.ndarray:
    """``count`` bytes at the current position, read with ``readinto`` into a numpy buffer (``buf``'s
    first bytes when given)."""
    buf = np.empty(count, dtype=np.uint8) if buf is None else buf[:count]
    if count:
        view = memoryview(buf)
        got = 0
        while got < count:
            r = f.readinto(view[got:])
            if not r:
                _fail("read error (the file changed while it was read, or the disk failed)")
            got += r
    return buf


def _copy_columns(buf: np.ndarray, m: int, record: int, offsets: List[int], file_dtype: str, out: np.ndarray):
    """out[v, j] := the value at byte offsets[j] of record v of buf, for v < m; runs of adjacent offsets
    are copied as one strided block."""
    dt = np.dtype(file_dtype)
    i = 0
    while i < len(offsets):
        j = i + 1
        while j < len(offsets) and offsets[j] == offsets[j - 1] + dt.itemsize:
            j += 1
        out[:, i:j] = np.ndarray(shape=(m, j - i), dtype=dt, buffer=buf, offset=offsets[i],
                                 strides=(record, dt.itemsize))
        i = j


# Vertex and face records are read in chunks of about this many bytes (the C++ reader's size, so that
# both report the same first problem of a file with several).
_CHUNK_BYTES = 8 << 20


def _read_vertices(f, n: int, layout: "_VertexLayout", rh: "_RadianceHeader", mesh: "RadianceMesh"):
    """Decodes the vertex element at the current file position into ``mesh``, chunk by chunk, checking
    each chunk (finite values, unit normals with radiance) as soon as it is decoded."""
    rec = layout.record
    targets = []  # (output array (n, w), offsets, file dtype, checked for finiteness)

    def target(offsets, file_dtype, dtype, finite):
        a = np.empty((n, len(offsets)), dtype=dtype)
        targets.append((a, offsets, file_dtype, finite))
        return a

    mesh.positions = target(layout.position, "<f4", np.float32, True)
    if layout.normal[0] >= 0:
        mesh.normals = target(layout.normal, "<f4", np.float32, True)
    if layout.color[0] >= 0:
        if layout.color[3] >= 0:
            mesh.colors = target(layout.color, "<u1", np.uint8, False)
        else:  # colours without alpha: alpha = 255
            mesh.colors = np.full((n, 4), 255, dtype=np.uint8)
            targets.append((mesh.colors[:, :3], layout.color[:3], "<u1", False))
    if layout.quality >= 0:
        mesh.quality = target([layout.quality], "<f4", np.float32, False).reshape(n)
    if rh.basis:
        K = basis_coefficient_count(rh.basis)
        mesh.basis = rh.basis
        mesh.reflected = rh.reflected
        mesh.tangents = target(layout.tangent, "<f4", np.float32, True)
        mesh.coefficients = target(layout.coefficients, "<f4", np.float32, True).reshape(n, 3, K)
    for (prefix, _, meta), offsets in zip(rh.blocks, layout.blocks):
        mesh.blocks[prefix] = Block(target(offsets, "<f4", np.float32, False), dict(meta))

    chunk = max(1, min(n, _CHUNK_BYTES // rec))
    buf = np.empty(chunk * rec, dtype=np.uint8) if n else None
    for start in range(0, n, chunk):
        m = min(chunk, n - start)
        data = _read_exact(f, m * rec, buf)
        for out, offsets, file_dtype, _ in targets:
            _copy_columns(data, m, rec, offsets, file_dtype, out[start:start + m])
        # This chunk's checks, at once and in the C++ reader's order (positions, normals, tangents,
        # coefficients, unit normals): a damaged or hostile file (e.g. a sparse file of zeros) is refused
        # after one chunk, before the rest of the arrays is touched.
        end = start + m
        _first_non_finite(mesh.positions[start:end], "position", start)
        if mesh.normals is not None:
            _first_non_finite(mesh.normals[start:end], "normal", start)
        if rh.basis:
            _first_non_finite(mesh.tangents[start:end], "radiance frame tangent", start)
            _first_non_finite(mesh.coefficients[start:end].reshape(m, -1), "radiance coefficient", start)
            problem = _unit_normal_problem(mesh.normals[start:end], start)
            if problem:
                _fail("invalid radiance data: " + problem)


class _FaceDecoder:
    """Decodes the face element: a vectorised path for records of fixed layout, a sequential one for
    the rest (lists whose lengths vary, e.g. a polygon), with the C++ reader's per-face checks."""

    def __init__(self, element: _Element, index_property: int, n: int, buf: np.ndarray, first: int = 0,
                 count: Optional[int] = None):
        """Decodes ``count`` faces (all by default) held by ``buf``; ``first`` is the index of the first
        one in the file (faces are decoded in chunks), for the messages."""
        self.e = element
        self.ip = index_property
        self.n = n
        self.buf = buf
        self.count = element.count if count is None else count
        self.first = first
        self.signed = element.properties[index_property].type == "int"

    def _truncated_face(self, f: int):
        _fail(f"file truncated: the face data ends inside face {self.first + f} of {self.e.count}; the file was "
              f"probably not completely written")

    def _check_indices(self, f0: int, raw: np.ndarray):
        """raw: (m, 3) uint32 indices of faces f0..f0+m-1; refuses the first bad one."""
        if raw.size == 0:
            return
        bad = raw >= self.n
        if self.signed:
            bad |= raw > 0x7FFFFFFF
        if not bad.any():
            return
        flat = int(np.argmax(bad.ravel()))
        f, value = self.first + f0 + flat // 3, int(raw.ravel()[flat])
        if self.signed and value > 0x7FFFFFFF:
            _fail(f"face {f} has a negative vertex index {value - (1 << 32)}")
        _fail(f"face {f} references vertex {value} but the file has only {self.n} vertices: vertex index out of range")

    def _sequential(self, f: int, cursor: int, out: np.ndarray, single: bool = False) -> Tuple[int, List[int]]:
        """Decodes faces from f (at byte ``cursor``) one by one; returns the end cursor and, with
        ``single``, the list lengths of that one face."""
        buf, end = self.buf, len(self.buf)
        lengths: List[int] = []
        last = f + 1 if single else self.count
        while f < last:
            lengths = []
            for pi, p in enumerate(self.e.properties):
                if not p.is_list:
                    if end - cursor < p.size:
                        self._truncated_face(f)
                    cursor += p.size
                    continue
                cdt = np.dtype(_TYPES[p.count_type][1])
                if end - cursor < cdt.itemsize:
                    self._truncated_face(f)
                length = int(np.frombuffer(buf, dtype=cdt, count=1, offset=cursor)[0])
                cursor += cdt.itemsize
                lengths.append(length)
                if pi == self.ip:
                    if length != 3:
                        _fail(f"face {self.first + f} has {length} vertices but only triangle meshes are supported: triangulate "
                              f"the mesh first (e.g. in MeshLab: Filters > Polygonal and Quad Mesh > Turn into a "
                              f"Pure-Triangular mesh) and save it again")
                    if end - cursor < 12:
                        self._truncated_face(f)
                    raw = np.frombuffer(buf, dtype="<u4", count=3, offset=cursor).astype(np.uint32)
                    self._check_indices(f, raw.reshape(1, 3))
                    out[f] = raw
                    cursor += 12
                else:
                    if length < 0:
                        _fail(f"face {self.first + f} has a negative length in list property {_shown(p.name)}")
                    size = length * p.size
                    if end - cursor < size:
                        self._truncated_face(f)
                    cursor += size
            f += 1
        return cursor, lengths

    def decode(self) -> Tuple[np.ndarray, int]:
        """(F, 3) uint32 indices and the number of bytes the element takes."""
        out = np.empty((self.count, 3), dtype=np.uint32)
        if self.count == 0:
            return out, 0
        # The first face, sequentially: its list lengths give the record layout assumed for all.
        record, lengths = self._sequential(0, 0, out, single=True)
        offsets = []  # (offset of each list's length field, its dtype, expected length)
        index_offset = None
        cursor, li = 0, 0
        for pi, p in enumerate(self.e.properties):
            if not p.is_list:
                cursor += p.size
                continue
            cdt = np.dtype(_TYPES[p.count_type][1])
            offsets.append((cursor, cdt, lengths[li]))
            cursor += cdt.itemsize
            if pi == self.ip:
                index_offset = cursor
            cursor += lengths[li] * p.size
            li += 1
        # Faces 1.. with the same layout, as strided views; stop at the first face that differs.
        m = min(self.count, len(self.buf) // record)
        same = m
        for off, cdt, expected in offsets:
            view = np.ndarray(shape=(m,), dtype=cdt, buffer=self.buf, offset=off, strides=(record,))
            differs = view != expected
            if differs.any():
                same = min(same, int(np.argmax(differs)))
        if same > 1:
            raw = np.ndarray(shape=(same - 1, 3), dtype="<u4", buffer=self.buf, offset=record + index_offset,
                             strides=(record, 4))
            self._check_indices(1, raw)
            out[1:same] = raw
        if same == self.count:
            return out, same * record
        cursor, _ = self._sequential(same, same * record, out)
        return out, cursor


# ---------------------------------------------------------------------------------------------------
# Reading


def read_rply(path: PathLike) -> RadianceMesh:
    """Reads a Radiance PLY file (``docs/radiance-ply-format.md``, section "Reader"), or a plain binary
    little-endian triangle PLY (then without radiance).

    Strict like the C++ reader: anything it cannot read exactly raises :class:`RadianceFileError`
    (a ``ValueError``) whose message starts with ``cannot load '<path>':`` and says what is wrong and how
    to fix it.  The layout of every element is checked against the file size before any allocation.
    With radiance data, ``normals`` are the frame normals and must be unit length."""
    path = os.fspath(path)
    try:
        return _read(path)
    except RadianceFileError as e:
        raise RadianceFileError(f"cannot load '{path}': {e}") from None
    except MemoryError:
        raise RadianceFileError(f"cannot load '{path}': not enough memory") from None


def _read(path: str) -> RadianceMesh:
    if os.path.isdir(path):
        _fail("it is a folder, not a file")
    try:
        f = open(path, "rb", buffering=0)
    except OSError as e:
        _fail(f"cannot open the file: {e.strerror or e}")
    with f:
        file_size = os.fstat(f.fileno()).st_size
        head_bytes = min(file_size, _MAX_HEADER_BYTES)
        head = f.read(head_bytes) if head_bytes else b""
        while len(head) < head_bytes:
            more = f.read(head_bytes - len(head))
            if not more:
                _fail("read error in the header (the file changed or the disk failed)")
            head += more
        elements, comments, data_offset = _parse_header(head, head_bytes == file_size)
        del head
        rh = _parse_radiance_comments(comments)

        # Layout of every element, checked before reading any data.
        vertex = next((e for e in elements if e.name == "vertex"), None)
        if vertex is None:
            _fail("the PLY file has no vertex element")
        face = next((e for e in elements if e.name == "face"), None)
        if vertex.count > _MAX_ELEMENT_COUNT:
            _fail(f"the header declares {vertex.count} vertices, more than this format supports "
                  f"({_MAX_ELEMENT_COUNT}); the header is probably damaged")
        if face is not None and face.count > _MAX_ELEMENT_COUNT:
            _fail(f"the header declares {face.count} faces, more than this format supports "
                  f"({_MAX_ELEMENT_COUNT}); the header is probably damaged")
        layout = _plan_vertices(vertex, rh)
        index_property, face_min_record = _plan_faces(face) if face is not None else (0, 0)
        # Refused even when empty: the rule is the same for every count (the specification says so),
        # and an empty one is still a declaration that a save would drop.
        for e in elements:
            if e is not vertex and e is not face and e.has_list:
                _fail(f"element {_shown(e.name)} has list properties (variable-size records) and is not a face "
                      f"element; this reader cannot skip such elements safely, even empty ones: remove the element "
                      f"and its property lines from the header (e.g. re-save the mesh from MeshLab)")

        # Sizes against the file size, before allocating anything.
        data_bytes = file_size - data_offset
        face_size_known = face is None or len(face.properties) == 1 or \
            sum(p.is_list for p in face.properties) == 1
        needed = 0
        face_offset = 0
        for e in elements:
            record = face_min_record if e is face else e.scalar_bytes
            size = e.count * record
            if needed + size > data_bytes:
                found = data_bytes - min(needed, data_bytes)
                at_least = "at least " if (e is face and not face_size_known) else ""
                data, records, count_name = (("vertex data", "vertices", "vertex count") if e is vertex else
                                             ("face data", "faces", "face count") if e is face else
                                             (f"data for element {_shown(e.name)}", "records", "element count"))
                _fail(f"file truncated: expected {at_least}{size} bytes of {data}, found {found}: the header declares "
                      f"{e.count} {records} of {at_least}{record} bytes each; the file was probably not completely "
                      f"written, or its header declares a wrong {count_name}")
            if e is face:
                face_offset = data_offset + needed
            needed += size
        # With triangles only the data size is exact; a polygon mesh is larger (the face decoder says
        # "triangulate" then).
        if face_size_known and data_bytes > needed and (face is None or face.count == 0):
            _fail(_trailing(data_bytes - needed))
        n = vertex.count
        if n > _MAX_WRITTEN_VERTEX_COUNT:
            _fail(f"the file has {n} vertices; this Python reader stores vertex indices as int32 and supports at "
                  f"most 2^31 vertices")

        mesh = RadianceMesh(positions=np.zeros((0, 3), np.float32))
        if layout.unknown and n > 0:
            one = len(layout.unknown) == 1
            names = ", ".join(_shown(u) for u in layout.unknown)
            mesh.skipped.append(f"vertex {'property' if one else 'properties'} {names} of the file "
                                f"{'is' if one else 'are'} not part of the radiance PLY format and "
                                f"{'was' if one else 'were'} not loaded (saving the mesh will not write "
                                f"{'it' if one else 'them'}; to keep such data, declare it as a block: 'comment "
                                f"block <prefix> width <n>' with properties <prefix>_0..<prefix>_<n-1>)")
        for e in elements:
            if e is vertex or e.count == 0:
                continue
            if e is face:
                names = ", ".join(_shown(p.name) for i, p in enumerate(e.properties) if i != index_property)
                if names:
                    mesh.skipped.append(f"face properties {names} were not loaded (the radiance PLY format stores "
                                        f"only the vertex indices of a face)")
                continue
            mesh.skipped.append(f"element {_shown(e.name)} ({e.count} records) is not part of the radiance PLY "
                                f"format and was not loaded (saving the mesh will not write it)")

        # Faces first when their size is known: they are small, and a damaged face block is then refused
        # before the (usually much larger) vertex data is read.  In chunks, as the vertices.
        faces_done = False
        if face is not None and face_size_known:
            out = np.empty((face.count, 3), dtype=np.uint32)
            per_chunk = max(1, _CHUNK_BYTES // face_min_record)
            for f0 in range(0, face.count, per_chunk):
                m = min(per_chunk, face.count - f0)
                f.seek(face_offset + f0 * face_min_record)
                buf = _read_exact(f, m * face_min_record)
                raw, _ = _FaceDecoder(face, index_property, n, buf, first=f0, count=m).decode()
                out[f0:f0 + m] = raw
            mesh.faces = out.view(np.int32)  # indices < n <= 2^31
            faces_done = True
            # Every face was a triangle of exactly face_min_record bytes: the sizes are exact now.
            if data_bytes > needed:
                _fail(_trailing(data_bytes - needed))

        position = data_offset
        for e in elements:
            f.seek(position)
            if e is face and faces_done:
                position += e.count * face_min_record
                continue
            if e is face:
                size = file_size - position  # polygons or other lists: at most the rest of the file
            else:
                size = e.count * e.scalar_bytes
                # Checked above with the smallest face records; faces with longer lists before this
                # element may have used more.
                if position + size > file_size:
                    what = "vertex data" if e is vertex else f"data for element {_shown(e.name)}"
                    _fail(_truncated("", size, max(0, file_size - position), what)
                          + " (or the header declares a wrong count)")
            if e is vertex:
                _read_vertices(f, n, layout, rh, mesh)
                position += size
            elif e is face:
                buf = _read_exact(f, size)
                raw, used = _FaceDecoder(e, index_property, n, buf).decode()
                del buf
                mesh.faces = raw.view(np.int32)  # indices < n <= 2^31
                position += used
            else:
                position += size
        if position != file_size:
            _fail(_trailing(file_size - position))
    return mesh


def _first_non_finite(values: np.ndarray, what: str, first: int = 0):
    ok = np.isfinite(values).reshape(values.shape[0], -1).all(axis=1)
    if not ok.all():
        v = first + int(np.argmin(ok))
        _fail(f"vertex {v} has a {what} that is not a finite number (NaN or infinity); fix or remove that vertex "
              f"before saving")


def _unit_normal_problem(normals: np.ndarray, first: int = 0) -> str:
    """As ``RadianceField::validate``: | |n|^2 - 1 | <= 1e-3 in float arithmetic."""
    n = normals.astype(np.float32, copy=False)
    with np.errstate(over="ignore", invalid="ignore"):
        nn = n[:, 0] * n[:, 0] + n[:, 1] * n[:, 1] + n[:, 2] * n[:, 2]
        bad = ~(np.abs(nn - np.float32(1.0)) <= np.float32(_UNIT_NORMAL_TOLERANCE))
    if not bad.any():
        return ""
    v = int(np.argmax(bad))
    return f"normal of vertex {first + v} is not unit length (|n|^2 = {float(nn[v]):g})"


# ---------------------------------------------------------------------------------------------------
# Validation for writing


class _Checked:
    """The mesh's arrays converted to the file's types, after validation."""

    def __init__(self):
        self.positions = None
        self.normals = None
        self.colors = None
        self.quality = None
        self.basis = None
        self.reflected = False
        self.tangents = None
        self.coefficients = None
        self.faces = None
        self.blocks: List[Tuple[str, np.ndarray, List[Tuple[str, str]]]] = []


def _float_array(value, name: str, shape: Tuple[int, ...], shape_text: str) -> np.ndarray:
    try:
        a = np.asarray(value)
    except Exception as e:  # noqa: BLE001 - anything numpy cannot convert
        _fail(f"{name} is not an array ({e})")
    if a.dtype.kind not in "fiu":
        _fail(f"{name} has dtype {a.dtype}, expected float32 (real numbers)")
    if a.shape != shape:
        _fail(f"{name} has shape {a.shape}, expected {shape_text}")
    with np.errstate(over="ignore", invalid="ignore"):
        return np.ascontiguousarray(a, dtype="<f4")


def _check_finite(a: np.ndarray, name: str, what: str, how: str):
    rows = max(1, _CHUNK_BYTES // max(1, a[:1].nbytes))
    for start in range(0, a.shape[0], rows):
        part = a[start:start + rows]
        if np.isfinite(part).all():
            continue
        ok = np.isfinite(part).reshape(part.shape[0], -1).all(axis=1)
        v = start + int(np.argmin(ok))
        _fail(f"vertex {v} has a {what} that is not a finite number (NaN or infinity, or too large for float32) "
              f"in {name}; {how}")


def _check(mesh: RadianceMesh) -> _Checked:
    """Validates ``mesh`` as ``validateRadianceMesh`` does, plus the Python types; returns the arrays in
    the file's types.  Raises RadianceFileError (message without the path)."""
    c = _Checked()
    if mesh.positions is None:
        _fail("positions is missing: an (N, 3) float32 array is required")
    pos = np.asarray(mesh.positions)
    if pos.ndim != 2 or pos.shape[1] != 3:
        _fail(f"positions has shape {pos.shape}, expected (N, 3)")
    n = pos.shape[0]
    if n > _MAX_WRITTEN_VERTEX_COUNT:
        _fail(f"the mesh has {n} vertices; the format supports at most 2^31")
    c.positions = _float_array(pos, "positions", (n, 3), "(N, 3)")
    _check_finite(c.positions, "positions", "position", "fix or remove that vertex before saving")

    if mesh.normals is not None:
        c.normals = _float_array(mesh.normals, "normals", (n, 3), f"({n}, 3) (3 per vertex) or None")
        _check_finite(c.normals, "normals", "normal", "fix or recompute the normals before saving")

    if mesh.colors is not None:
        col = np.asarray(mesh.colors)
        if col.shape != (n, 4):
            _fail(f"colors has shape {col.shape}, expected ({n}, 4) (RGBA per vertex) or None"
                  + ("; add an alpha column, e.g. np.concatenate([rgb, np.full((N, 1), 255, np.uint8)], axis=1)"
                     if col.shape == (n, 3) else ""))
        if col.dtype.kind not in "iu":
            _fail(f"colors has dtype {col.dtype}, expected uint8 (0..255); convert e.g. with "
                  f"np.clip(np.round(c * 255), 0, 255).astype(np.uint8)")
        if col.size and (col.min() < 0 or col.max() > 255):
            _fail("colors has values outside 0..255; clip them and convert to uint8")
        c.colors = np.ascontiguousarray(col, dtype=np.uint8)

    if mesh.quality is not None:
        c.quality = _float_array(mesh.quality, "quality", (n,), f"({n},) (1 per vertex) or None")
        # not checked: "quality and extra-block values are user data" (NaN allowed), as in the specification

    faces = mesh.faces
    if faces is None:
        faces = _no_faces()
    fa = np.asarray(faces)
    if fa.size == 0 and fa.ndim <= 2:
        fa = fa.reshape(0, 3)
    if fa.ndim != 2 or fa.shape[1] != 3:
        _fail(f"faces has shape {fa.shape}, expected (F, 3): triangles only (triangulate the mesh first)")
    if fa.dtype.kind not in "iu":
        _fail(f"faces has dtype {fa.dtype}, expected int32 vertex indices")
    if fa.shape[0] > _MAX_ELEMENT_COUNT:
        _fail("too many faces (at most 2^32-1)")
    if fa.size:
        bad = (fa < 0) | (fa >= n)
        if bad.any():
            flat = int(np.argmax(bad.ravel()))
            _fail(f"face {flat // 3} references vertex {int(fa.ravel()[flat])} but the mesh has {n} vertices "
                  f"(indices are 0-based, 0..N-1)")
    c.faces = np.ascontiguousarray(fa, dtype="<i4")

    if mesh.basis is None:
        if mesh.coefficients is not None or mesh.tangents is not None:
            _fail("coefficients or tangents are set but basis is None; set basis (e.g. 'PB4') or remove them")
        if mesh.reflected:
            _fail("reflected is True but the mesh has no radiance (basis is None); the file cannot record it")
    else:
        if parse_basis(mesh.basis) is None:
            _fail(f"unknown radiance basis {_shown(str(mesh.basis))} (supported: PB0..PB{_MAX_PB_DEGREE}, "
                  f"SH0..SH{_MAX_SH_DEGREE})")
        c.basis = _basis_name(mesh.basis)
        K = basis_coefficient_count(c.basis)
        if mesh.reflected not in (True, False, 0, 1):
            _fail(f"reflected must be True or False, not {mesh.reflected!r}")
        c.reflected = bool(mesh.reflected)
        if c.normals is None:
            _fail("radiance data needs the per-vertex frame normals: set normals ((N, 3), unit length)")
        if mesh.tangents is None:
            _fail("radiance data needs the per-vertex frame tangents: set tangents ((N, 3), the rf_tx rf_ty rf_tz "
                  "of the file)")
        if mesh.coefficients is None:
            _fail(f"basis is {c.basis} but coefficients is None: set an ({n}, 3, {K}) array or basis = None")
        c.tangents = _float_array(mesh.tangents, "tangents", (n, 3), f"({n}, 3)")
        c.coefficients = _float_array(mesh.coefficients, "coefficients", (n, 3, K),
                                      f"({n}, 3, {K}) for basis {c.basis} (coefficients[v, c, k] = rf_<c>_<k>)")
        _check_finite(c.tangents, "tangents", "radiance frame tangent", "fix the frame before saving")
        _check_finite(c.coefficients, "coefficients", "radiance coefficient", "fix or refit that vertex")
        problem = _unit_normal_problem(c.normals)
        if problem:
            _fail(f"invalid radiance field: {problem}; the normals are the radiance frame normals and must be unit "
                  f"length (normalise them, e.g. normals / np.linalg.norm(normals, axis=1, keepdims=True))")

    if mesh.blocks is None:
        return c
    if not isinstance(mesh.blocks, dict):
        _fail(f"blocks must be a dict prefix -> Block, not {type(mesh.blocks).__name__}")
    for prefix, block in mesh.blocks.items():
        if not isinstance(prefix, str) or not _is_identifier(prefix):
            _fail(f"extra block prefix {_shown(str(prefix))} is not an identifier ([A-Za-z_][A-Za-z0-9_]*, at most "
                  f"64 characters)")
        if _is_reserved_prefix(prefix):
            _fail(f"extra block prefix {_shown(prefix)} is reserved (rf, rf_*)")
        if not isinstance(block, Block):
            _fail(f"extra block {_shown(prefix)} must be a Block(values, meta), not {type(block).__name__}")
        values = np.asarray(block.values)
        if values.ndim != 2 or values.shape[0] != n:
            _fail(f"extra block {_shown(prefix)} has values of shape {values.shape}, expected ({n}, width)"
                  + ("; reshape a single column with values.reshape(-1, 1)" if values.shape == (n,) else ""))
        width = values.shape[1]
        if not 1 <= width <= _MAX_BLOCK_WIDTH:
            _fail(f"extra block {_shown(prefix)} has width {width} (1..{_MAX_BLOCK_WIDTH})")
        values = _float_array(values, f"block {prefix!r} values", (n, width), f"({n}, width)")
        meta = block.meta if block.meta is not None else {}
        if not isinstance(meta, dict):
            _fail(f"extra block {_shown(prefix)} has meta of type {type(meta).__name__}, expected dict[str, str]")
        for key, value in meta.items():
            if not isinstance(key, str) or not isinstance(value, str):
                _fail(f"metadata of block {_shown(prefix)} must map str to str (key {key!r}: {value!r}); convert "
                      f"numbers with str()")
            if not _is_metadata_key(key):
                _fail(f"metadata key {_shown(key)} of block {_shown(prefix)} is empty or contains whitespace")
            if not _is_metadata_value(value):
                _fail(f"metadata value of key {_shown(key)} of block {_shown(prefix)} contains a control character "
                      f"(e.g. a line break)")
        # std::map order: bytewise on the key.
        c.blocks.append((prefix, values, sorted(meta.items(), key=lambda kv: _utf8(kv[0]))))
    return c


def validate_mesh(mesh: RadianceMesh) -> None:
    """Raises :class:`RadianceFileError` when :func:`write_rply` would refuse ``mesh`` (the checks of
    ``validateRadianceMesh``, specification section "Writer", step 1)."""
    _check(mesh)


# ---------------------------------------------------------------------------------------------------
# Writing


def _header(c: _Checked, n: int, f: int) -> bytes:
    """The header, line for line as ``makeHeader`` in common/io/radiance_ply.cpp."""
    lines = ["ply", "format binary_little_endian 1.0", f"comment radiance_format_version {FORMAT_VERSION}"]
    if c.basis is not None:
        lines += [f"comment radiance_basis {c.basis}", f"comment radiance_reflected {1 if c.reflected else 0}",
                  "comment radiance_channels rgb", "comment radiance_color_space linear",
                  "comment radiance_frame tangent_normal"]
    for prefix, values, meta in c.blocks:
        lines.append(f"comment block {prefix} width {values.shape[1]}")
        for key, value in meta:
            lines.append(f"comment block_meta {prefix} {key}" + (f" {value}" if value else ""))
    lines += [f"element vertex {n}", "property float x", "property float y", "property float z"]
    if c.normals is not None:
        lines += ["property float nx", "property float ny", "property float nz"]
    if c.colors is not None:
        lines += ["property uchar red", "property uchar green", "property uchar blue", "property uchar alpha"]
    if c.quality is not None:
        lines.append("property float quality")
    if c.basis is not None:
        lines += ["property float rf_tx", "property float rf_ty", "property float rf_tz"]
        K = c.coefficients.shape[2]
        lines += [f"property float rf_{ch}_{k}" for ch in _CHANNELS for k in range(K)]
    for prefix, values, _ in c.blocks:
        lines += [f"property float {prefix}_{i}" for i in range(values.shape[1])]
    lines += [f"element face {f}", "property list uchar int vertex_indices", "end_header"]
    return ("\n".join(lines) + "\n").encode("utf-8", "surrogateescape")


def _vertex_chunks(c: _Checked, n: int):
    """The vertex records (the properties of each vertex packed in header order, as the C++ writer's
    copy runs), as (rows, record) uint8 arrays of about _CHUNK_BYTES, one reused buffer."""
    parts = [c.positions]
    if c.normals is not None:
        parts.append(c.normals)
    if c.colors is not None:
        parts.append(c.colors)
    if c.quality is not None:
        parts.append(c.quality.reshape(n, 1))
    if c.basis is not None:
        parts.append(c.tangents)
        parts.append(c.coefficients.reshape(n, 3 * c.coefficients.shape[2]))
    parts += [values for _, values, _ in c.blocks]
    parts = [np.ascontiguousarray(p).reshape(n, int(np.prod(p.shape[1:]))).view(np.uint8)
             for p in parts]  # (n, bytes) each
    record = sum(p.shape[1] for p in parts)
    rows = max(1, min(n, _CHUNK_BYTES // record))
    buf = np.empty((rows, record), dtype=np.uint8)
    for start in range(0, n, rows):
        m = min(rows, n - start)
        col = 0
        for p in parts:
            w = p.shape[1]
            buf[:m, col:col + w] = p[start:start + m]
            col += w
        yield buf[:m]


def _face_chunks(faces: np.ndarray):
    """The face records (the byte 3 and three little-endian int32 indices), in chunks."""
    nf = faces.shape[0]
    rows = max(1, min(nf, _CHUNK_BYTES // 13))
    buf = np.empty((rows, 13), dtype=np.uint8)
    buf[:, 0] = 3
    raw = faces.view(np.uint8).reshape(nf, 12)
    for start in range(0, nf, rows):
        m = min(rows, nf - start)
        buf[:m, 1:] = raw[start:start + m]
        yield buf[:m]


_counter = itertools.count()


def write_rply(path: PathLike, mesh: RadianceMesh) -> None:
    """Writes ``mesh`` to ``path`` as a Radiance PLY file (``docs/radiance-ply-format.md``, section
    "Writer"), byte-identical to what ``rad::writeRadiancePly`` writes for the same data.

    Validates everything first (array shapes and types, finite positions/normals/tangents/coefficients,
    face indices in 0..N-1, unit-length normals with radiance, block prefixes/widths/metadata); float64
    arrays are converted to float32.  Then removes the temporary files of earlier saves to ``path`` whose
    writer process is dead (killed mid-save), writes a temporary file ``<path>.part-<pid>-<n>-<t>`` in the
    same folder, ``fsync``s it and renames it over ``path`` (atomic on POSIX).  Any problem raises
    :class:`RadianceFileError` (``cannot save '<path>': ...``) and leaves an existing file at ``path``
    untouched."""
    path = os.fspath(path)
    try:
        c = _check(mesh)
        n, nf = c.positions.shape[0], c.faces.shape[0]
        header = _header(c, n, nf)
    except RadianceFileError as e:
        raise RadianceFileError(f"cannot save '{path}': {e}") from None
    except MemoryError:
        raise RadianceFileError(f"cannot save '{path}': not enough memory") from None

    _remove_stale_temporaries(path)
    temp, fd, error = "", -1, None
    for _ in range(16):
        temp = f"{path}.part-{os.getpid()}-{next(_counter)}-{time.monotonic_ns() % 1000000}"
        try:
            fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0), 0o666)
            break
        except FileExistsError as e:
            error = e
        except OSError as e:
            error = e
            break
    if fd < 0:
        raise RadianceFileError(f"cannot save '{path}': cannot create the temporary file '{temp}': "
                                f"{getattr(error, 'strerror', None) or error}; check that the folder exists and is "
                                f"writable")
    try:
        with os.fdopen(fd, "wb") as out:
            out.write(header)
            for records in itertools.chain(_vertex_chunks(c, n), _face_chunks(c.faces)):
                out.write(memoryview(records).cast("B"))
            out.flush()
            os.fsync(out.fileno())
    except OSError as e:
        _remove_quietly(temp)
        raise RadianceFileError(f"cannot save '{path}': write error: {e.strerror or e} (the disk may be full); "
                                f"nothing was written") from None
    except BaseException:
        _remove_quietly(temp)
        raise
    try:
        os.replace(temp, path)
    except OSError as e:
        _remove_quietly(temp)
        raise RadianceFileError(f"cannot save '{path}': cannot replace the file: {e.strerror or e}") from None


_TEMPORARY_SUFFIX = re.compile(r"\.part-(\d+)-(\d+)-(\d+)\Z")


def _remove_stale_temporaries(path: str):
    """Removes the temporary files ``<path>.part-<pid>-<n>-<t>`` that a writer killed mid-save left
    behind, as the C++ writer does: only those whose writer process no longer exists on this machine (a
    live writer's file is never touched); nothing on Windows."""
    if os.name == "nt":
        return
    folder, name = os.path.split(os.path.abspath(path))
    try:
        entries = os.listdir(folder)
    except OSError:
        return
    for entry in entries:
        if not entry.startswith(name + ".part-"):
            continue
        m = _TEMPORARY_SUFFIX.match(entry, len(name))
        if not m:
            continue
        pid = int(m.group(1))
        if pid <= 0 or pid > 0x7FFFFFFF:
            continue
        try:
            os.kill(pid, 0)
            continue  # alive
        except ProcessLookupError:
            pass
        except OSError:
            continue  # e.g. another user's live process: not ours to judge
        full = os.path.join(folder, entry)
        if os.path.isfile(full) and not os.path.islink(full):
            _remove_quietly(full)


def _remove_quietly(path: str):
    try:
        os.remove(path)
    except OSError:
        pass
