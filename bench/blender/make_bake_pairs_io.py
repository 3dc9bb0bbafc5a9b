# The mesh helpers of make_bake_pairs.py and make_scan_pair.py (run inside Blender): triangulate,
# smooth shading, and the files MeshLab reads (see make_bake_pairs.py for their layout).
import bmesh


def triangulate(obj):
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    bmesh.ops.triangulate(bm, faces=bm.faces[:], quad_method="FIXED", ngon_method="EAR_CLIP")
    bm.to_mesh(obj.data)
    bm.free()


def smooth(obj):
    for p in obj.data.polygons:
        p.use_smooth = True


def write_high_ply(obj, path):
    mesh = obj.data
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\n" % len(mesh.vertices))
        f.write("property float x\nproperty float y\nproperty float z\n")
        f.write("property float nx\nproperty float ny\nproperty float nz\n")
        f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(mesh.polygons))
        for v in mesh.vertices:
            f.write("%r %r %r %r %r %r\n" % (tuple(v.co) + tuple(v.normal)))
        for p in mesh.polygons:
            f.write("3 %d %d %d\n" % tuple(p.vertices))


def write_low(obj, ply_path, corners_path):
    mesh = obj.data
    mesh.calc_tangents()
    uv = mesh.uv_layers.active.data
    split = {}
    vertices = []
    faces = []
    with open(corners_path, "w") as corners:
        for p in mesh.polygons:
            face = []
            for li in range(p.loop_start, p.loop_start + 3):
                loop = mesh.loops[li]
                v = mesh.vertices[loop.vertex_index]
                key = (loop.vertex_index, tuple(uv[li].uv))
                if key not in split:
                    split[key] = len(vertices)
                    vertices.append(tuple(v.co) + tuple(v.normal) + tuple(uv[li].uv))
                face.append(split[key])
                corners.write("%r %r %r %r %r %r %r %r %r %r %r %r\n" % (
                    tuple(v.co) + tuple(loop.normal) + tuple(uv[li].uv) + tuple(loop.tangent) + (loop.bitangent_sign,)))
            faces.append(face)
    with open(ply_path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\n" % len(vertices))
        f.write("property float x\nproperty float y\nproperty float z\n")
        f.write("property float nx\nproperty float ny\nproperty float nz\n")
        f.write("property float texture_u\nproperty float texture_v\n")
        f.write("element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces))
        for v in vertices:
            f.write("%r %r %r %r %r %r %r %r\n" % v)
        for face in faces:
            f.write("3 %d %d %d\n" % tuple(face))
