#!/usr/bin/env python3
"""An independent, minimal reader for binary little-endian PLY files (pure Python 3, `struct` only).

It shares no code with the C++ reader (common/io/radiance_ply.cpp): integration tests use it to show
that any PLY reader can read the geometry and, by property name, the radiance coefficients of the
files our writer produces (docs/radiance-ply-format.md).

Library use:
    ply = read_ply(path)
    ply.comments                          # ['radiance_format_version 1', 'radiance_basis PB4', ...]
    ply.elements                          # [Element(name, count, properties), ...] in file order
    ply.data['vertex']['x']               # list of floats, one per vertex
    read_ply(path, properties=['x'])      # decode only some properties (faster on large files)
    ply.data['face']['vertex_indices']    # list of lists
    ply.comment_value('radiance_basis')   # 'PB4'
    ply['elements']['vertex']['x'], ply['comments'], ply['layout']['vertex']   # dictionary-style access

Command line:
    python3 ply_reader.py FILE --summary
    python3 ply_reader.py FILE --dump-property NAME [--element ELEMENT]

Any scalar or list property of any element is supported. ASCII and big-endian files are refused.
"""

import argparse
import json
import struct
import sys

# PLY type name -> (struct code, size in bytes)
TYPES = {
    'char': ('b', 1), 'int8': ('b', 1),
    'uchar': ('B', 1), 'uint8': ('B', 1),
    'short': ('h', 2), 'int16': ('h', 2),
    'ushort': ('H', 2), 'uint16': ('H', 2),
    'int': ('i', 4), 'int32': ('i', 4),
    'uint': ('I', 4), 'uint32': ('I', 4),
    'float': ('f', 4), 'float32': ('f', 4),
    'double': ('d', 8), 'float64': ('d', 8),
}


class PlyError(Exception):
    pass


class Property:
    def __init__(self, name, type_name, count_type=None):
        self.name = name
        self.type = type_name            # scalar type, or list item type
        self.count_type = count_type     # None for scalars

    @property
    def is_list(self):
        return self.count_type is not None

    def describe(self):
        if self.is_list:
            return 'list %s %s %s' % (self.count_type, self.type, self.name)
        return '%s %s' % (self.type, self.name)


class Element:
    def __init__(self, name, count):
        self.name = name
        self.count = count
        self.properties = []


class PlyFile:
    def __init__(self):
        self.format = None
        self.comments = []     # text after "comment ", in order
        self.obj_info = []
        self.elements = []
        self.data = {}         # element name -> property name -> list of values
        self.trailing_bytes = 0

    def element(self, name):
        for e in self.elements:
            if e.name == name:
                return e
        return None

    # Dictionary-style access, used by the integration scripts:
    #   ply["comments"]                 header comments, text after "comment "
    #   ply["elements"]["vertex"]["x"]  property values (same lists as ply.data)
    #   ply["layout"]["vertex"]         [(name, size in bytes or None for lists, type, count type or None)]
    #                                   in file order: the record layout of the element
    #   ply["format"], ply["obj_info"], ply["trailing_bytes"]
    def __getitem__(self, key):
        if key == 'comments':
            return self.comments
        if key == 'elements':
            return self.data
        if key == 'layout':
            return {e.name: [(p.name, None if p.is_list else TYPES[p.type][1], p.type, p.count_type)
                             for p in e.properties] for e in self.elements}
        if key in ('format', 'obj_info', 'trailing_bytes'):
            return getattr(self, key)
        raise KeyError(key)

    def __contains__(self, key):
        return key in ('comments', 'elements', 'layout', 'format', 'obj_info', 'trailing_bytes')

    def comment_value(self, key):
        """Value of the first comment 'key value', or None."""
        for c in self.comments:
            parts = c.split(None, 1)
            if parts and parts[0] == key:
                return parts[1] if len(parts) > 1 else ''
        return None


def _parse_header(blob):
    if not (blob.startswith(b'ply\n') or blob.startswith(b'ply\r\n')):
        raise PlyError('not a PLY file (no "ply" first line)')
    ply = PlyFile()
    pos = 0
    line_number = 0
    while True:
        nl = blob.find(b'\n', pos)
        if nl < 0:
            raise PlyError('no end_header line')
        raw = blob[pos:nl]
        pos = nl + 1
        line_number += 1
        if raw.endswith(b'\r'):
            raw = raw[:-1]
        line = raw.decode('latin-1')
        if line_number == 1:
            continue
        words = line.split()
        if not words:
            continue
        keyword = words[0]
        if keyword == 'end_header':
            break
        if keyword == 'comment':
            ply.comments.append(line.split(None, 1)[1] if len(words) > 1 else '')
        elif keyword == 'obj_info':
            ply.obj_info.append(line.split(None, 1)[1] if len(words) > 1 else '')
        elif keyword == 'format':
            if len(words) != 3:
                raise PlyError('line %d: bad format line' % line_number)
            if words[1] != 'binary_little_endian':
                raise PlyError('format %s is not supported (binary_little_endian only)' % words[1])
            ply.format = words[1] + ' ' + words[2]
        elif keyword == 'element':
            if len(words) != 3 or not words[2].isdigit():
                raise PlyError('line %d: bad element line' % line_number)
            ply.elements.append(Element(words[1], int(words[2])))
        elif keyword == 'property':
            if not ply.elements:
                raise PlyError('line %d: property before any element' % line_number)
            if len(words) == 5 and words[1] == 'list':
                if words[2] not in TYPES or words[3] not in TYPES:
                    raise PlyError('line %d: unknown type' % line_number)
                prop = Property(words[4], words[3], words[2])
            elif len(words) == 3:
                if words[1] not in TYPES:
                    raise PlyError('line %d: unknown type %s' % (line_number, words[1]))
                prop = Property(words[2], words[1])
            else:
                raise PlyError('line %d: bad property line' % line_number)
            ply.elements[-1].properties.append(prop)
        else:
            raise PlyError('line %d: unknown keyword %s' % (line_number, keyword))
    if ply.format is None:
        raise PlyError('no format line')
    return ply, pos


def _read_fixed(element, blob, pos, wanted):
    """All records of an element without list properties. Only the wanted columns are decoded
    (the others are struct pad bytes), which keeps a one-column dump of a large file fast."""
    size = sum(TYPES[p.type][1] for p in element.properties)
    end = pos + size * element.count
    if end > len(blob):
        raise PlyError('file truncated in element %s: need %d bytes, have %d'
                       % (element.name, size * element.count, len(blob) - pos))
    keep = [p for p in element.properties if wanted is None or p.name in wanted]
    columns = {p.name: [] for p in keep}
    if element.count and keep:
        fmt = '<' + ''.join(TYPES[p.type][0] if (wanted is None or p.name in wanted) else '%dx' % TYPES[p.type][1]
                            for p in element.properties)
        rows = struct.iter_unpack(fmt, blob[pos:end])
        if len(keep) == 1:
            columns[keep[0].name] = [r[0] for r in rows]
        else:
            for p, values in zip(keep, zip(*rows)):
                columns[p.name] = list(values)
    return columns, end


def _read_variable(element, blob, pos, wanted):
    """Records with list properties, one property at a time (unwanted values are skipped)."""
    columns = {p.name: [] for p in element.properties if wanted is None or p.name in wanted}
    plan = []
    for p in element.properties:
        code, size = TYPES[p.type]
        column = columns.get(p.name, [])
        keep = p.name in columns
        if p.is_list:
            ccode, csize = TYPES[p.count_type]
            plan.append((column, keep, True, '<' + ccode, csize, code, size))
        else:
            plan.append((column, keep, False, '<' + code, size, None, None))
    n = len(blob)
    for i in range(element.count):
        for column, keep, is_list, fmt, size, item_code, item_size in plan:
            if pos + size > n:
                raise PlyError('file truncated in %s %d' % (element.name, i))
            if not is_list:
                if keep:
                    column.append(struct.unpack_from(fmt, blob, pos)[0])
                pos += size
                continue
            value, = struct.unpack_from(fmt, blob, pos)
            pos += size
            if value < 0:
                raise PlyError('negative list length in %s %d' % (element.name, i))
            if pos + value * item_size > n:
                raise PlyError('file truncated in %s %d' % (element.name, i))
            if keep:
                column.append(list(struct.unpack_from('<%d%s' % (value, item_code), blob, pos)))
            pos += value * item_size
    return columns, pos


def read_ply(path, properties=None):
    """Reads the file. `properties`: None to decode every property, or a collection of property
    names to decode only those (ply.data then holds only them; the whole file is still checked)."""
    wanted = None if properties is None else set(properties)
    with open(path, 'rb') as f:
        blob = f.read()
    ply, pos = _parse_header(blob)
    for element in ply.elements:
        if any(p.is_list for p in element.properties):
            columns, pos = _read_variable(element, blob, pos, wanted)
        else:
            columns, pos = _read_fixed(element, blob, pos, wanted)
        ply.data[element.name] = columns
    ply.trailing_bytes = len(blob) - pos
    return ply


def summary(ply):
    vertex = ply.element('vertex')
    face = ply.element('face')
    return {
        'format': ply.format,
        'vertex_count': vertex.count if vertex else 0,
        'face_count': face.count if face else 0,
        'vertex_properties': [p.name for p in vertex.properties] if vertex else [],
        'face_properties': [p.name for p in face.properties] if face else [],
        'elements': [{'name': e.name, 'count': e.count,
                      'properties': [p.describe() for p in e.properties]} for e in ply.elements],
        'comments': ply.comments,
        'obj_info': ply.obj_info,
        'trailing_bytes': ply.trailing_bytes,
    }


def _format_value(v):
    # repr of a Python float is the shortest text that reads back to the same double, and a float32
    # widened to double reads back to the same float32: the dump is lossless.
    return repr(v) if isinstance(v, float) else str(v)


def main(argv=None):
    parser = argparse.ArgumentParser(description='Minimal independent binary little-endian PLY reader.')
    parser.add_argument('file')
    parser.add_argument('--summary', action='store_true', help='print a JSON summary of the file')
    parser.add_argument('--dump-property', metavar='NAME', help='print the values of a property, one per line '
                        '(list values space-separated on one line)')
    parser.add_argument('--element', help='element of --dump-property (default: the first element that has it, '
                        'vertex first)')
    args = parser.parse_args(argv)
    if not args.summary and not args.dump_property:
        parser.error('nothing to do: give --summary and/or --dump-property NAME')
    try:
        ply = read_ply(args.file, [args.dump_property] if args.dump_property else [])
    except (PlyError, OSError) as e:
        print('ply_reader: %s: %s' % (args.file, e), file=sys.stderr)
        return 1
    if args.summary:
        print(json.dumps(summary(ply), indent=2))
    if args.dump_property:
        names = [args.element] if args.element else \
            sorted(ply.data, key=lambda n: (n != 'vertex', [e.name for e in ply.elements].index(n)))
        for name in names:
            columns = ply.data.get(name, {})
            if args.dump_property in columns:
                out = []
                for v in columns[args.dump_property]:
                    out.append(' '.join(_format_value(x) for x in v) if isinstance(v, list) else _format_value(v))
                sys.stdout.write('\n'.join(out) + ('\n' if out else ''))
                return 0
        print('ply_reader: %s: no property %s%s' % (args.file, args.dump_property,
                                                   ' in element ' + args.element if args.element else ''),
              file=sys.stderr)
        return 2
    return 0


if __name__ == '__main__':
    sys.exit(main())
