# Run inside Blender: blender -b PAIRS.blend --factory-startup -P render_compare.py -- \
#     SHAPE OUT_DIR OURS.glb OURS_16BIT.png BLENDER.npy [RESOLUTION SAMPLES]
# The render comparison of bench/bake_vs_blender.sh: does a low mesh with a baked normal map render
# like the high mesh? Cycles (CPU) renders, with the same camera, lights and material:
#   high          <SHAPE>_high, no normal map
#   ours_glb      our .glb imported by Blender's glTF add-on (its mesh, UVs and 8-bit normal texture)
#   ours_16       <SHAPE>_low with our 16-bit PNG
#   blender_float <SHAPE>_low with Blender's own Cycles bake (float image)
#   blender_8     the same map rounded to 8 bits (what an 8-bit PNG of it holds)
# and prints, for each low render against the high one, RMSE and mean absolute error of the linear
# RGB over the pixels both renders cover (alpha 1; silhouettes differ by the low mesh's facets,
# whatever the map) and over the whole image (background included).
# Lighting is made deterministic so that the error is the shading's, not Monte Carlo noise: two
# sun lamps of zero angle, a black world, no indirect bounces, a fixed seed (the same pixel-filter
# jitter in every render).
import os
import sys

import numpy

if not hasattr(numpy, "bool"):  # Debian 12's Blender 3.4 glTF add-on calls numpy.bool (numpy 1.24 removed it)
    numpy.bool = bool
import bpy  # noqa: E402
from mathutils import Matrix, Vector  # noqa: E402

args = sys.argv[sys.argv.index("--") + 1:]
shape, out_dir, glb_path, ours16_path, blender_npy = args[:5]
resolution = int(args[5]) if len(args) > 5 else 256
samples = int(args[6]) if len(args) > 6 else 16
os.makedirs(out_dir, exist_ok=True)
np = numpy

scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
scene.cycles.seed = 0
scene.cycles.use_animated_seed = False
scene.cycles.max_bounces = 0
scene.cycles.diffuse_bounces = 0
scene.cycles.glossy_bounces = 0
scene.cycles.transmission_bounces = 0
scene.render.film_transparent = True
scene.render.resolution_x = scene.render.resolution_y = resolution
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_mode = "RGBA"
scene.render.image_settings.color_depth = "32"
if scene.world is None:
    scene.world = bpy.data.worlds.new("world")
scene.world.use_nodes = True
scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0

high = bpy.data.objects[shape + "_high"]
low = bpy.data.objects[shape + "_low"]
for obj in list(scene.objects):
    if obj.type in {"CAMERA", "LIGHT"}:
        bpy.data.objects.remove(obj)

# Frame the high mesh: camera on a fixed direction at 3.2 bounding radii.
corners = [high.matrix_world @ Vector(c) for c in high.bound_box]
center = sum(corners, Vector()) / 8.0
radius = max((c - center).length for c in corners)
camera_data = bpy.data.cameras.new("camera")
camera_data.lens = 50
camera = bpy.data.objects.new("camera", camera_data)
scene.collection.objects.link(camera)
camera.location = center + Vector((0.55, -0.65, 0.52)).normalized() * 3.2 * radius
camera.rotation_euler = (center - camera.location).to_track_quat("-Z", "Y").to_euler()
scene.camera = camera
for name, direction, color, strength in (("key", (0.6, -0.3, 0.8), (1.0, 0.95, 0.9), 3.0),
                                         ("fill", (-0.8, -0.6, 0.2), (0.6, 0.7, 1.0), 1.2),
                                         ("rim", (-0.2, 0.9, 0.4), (1.0, 1.0, 1.0), 1.5)):
    light_data = bpy.data.lights.new(name, "SUN")
    light_data.angle = 0.0
    light_data.energy = strength
    light_data.color = color
    light = bpy.data.objects.new(name, light_data)
    light.rotation_euler = Vector(direction).to_track_quat("Z", "Y").to_euler()
    scene.collection.objects.link(light)


def material(name, image=None, uv_map=""):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes = m.node_tree.nodes
    bsdf = nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.7, 0.7, 0.7, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.3
    bsdf.inputs["Specular"].default_value = 0.5
    if image is not None:
        image.colorspace_settings.name = "Non-Color"
        tex = nodes.new("ShaderNodeTexImage")
        tex.image = image
        tex.interpolation = "Linear"
        normal_map = nodes.new("ShaderNodeNormalMap")
        normal_map.space = "TANGENT"
        normal_map.uv_map = uv_map
        m.node_tree.links.new(tex.outputs["Color"], normal_map.inputs["Color"])
        m.node_tree.links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    return m


def assign(obj, m):
    obj.data.materials.clear()
    obj.data.materials.append(m)


def float_image(name, rgb_top_to_bottom):
    # Through an OpenEXR file: a generated image's pixels set from Python do not reach Cycles in
    # a background render.
    size = rgb_top_to_bottom.shape[0]
    rgba = np.ones((size, size, 4), dtype=np.float32)
    rgba[:, :, :3] = rgb_top_to_bottom[::-1]
    image = bpy.data.images.new(name, size, size, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(rgba.ravel())
    path = os.path.join(out_dir, "%s_%s.exr" % (shape, name))
    image.filepath_raw = path
    image.file_format = "OPEN_EXR"
    image.save()
    bpy.data.images.remove(image)
    loaded = bpy.data.images.load(path)
    loaded.colorspace_settings.name = "Non-Color"
    back = np.array(loaded.pixels[:], dtype=np.float32).reshape(size, size, 4)
    assert np.abs(back - rgba).max() < 1e-6, "the map did not survive its OpenEXR file"
    return loaded


# Our .glb, as a user would bring it in. glTF is +Y up: the add-on turns it to Blender's +Z up
# (x, y, z) -> (x, -z, y); our file holds the low mesh's own coordinates, so the inverse rotation
# puts the imported object back where the low mesh is.
before = set(bpy.data.objects)
result = bpy.ops.import_scene.gltf(filepath=glb_path)
assert result == {"FINISHED"}, result
imported = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
assert len(imported) == 1, imported
ours = imported[0]
ours.matrix_world = Matrix(((1, 0, 0, 0), (0, 0, 1, 0), (0, -1, 0, 0), (0, 0, 0, 1))) @ ours.matrix_world
glb_image = next(n.image for m in ours.data.materials for n in m.node_tree.nodes
                 if n.type == "TEX_IMAGE" and any(l.to_node.type == "NORMAL_MAP" for l in n.outputs["Color"].links))
low_world = [low.matrix_world @ v.co for v in low.data.vertices]
ours_world = [ours.matrix_world @ v.co for v in ours.data.vertices]
lo = Vector([min(v[k] for v in low_world) for k in range(3)])
lo2 = Vector([min(v[k] for v in ours_world) for k in range(3)])
hi = Vector([max(v[k] for v in low_world) for k in range(3)])
hi2 = Vector([max(v[k] for v in ours_world) for k in range(3)])
assert (lo - lo2).length < 1e-4 * radius and (hi - hi2).length < 1e-4 * radius, (lo, lo2, hi, hi2)

blender_map = np.load(blender_npy).astype(np.float32)
variants = {
    "ours_glb": (ours, material("ours_glb", glb_image, ours.data.uv_layers.active.name)),
    "ours_16": (low, material("ours_16", bpy.data.images.load(ours16_path), low.data.uv_layers.active.name)),
    "blender_float": (low, material("blender_float", float_image("blender_float", blender_map),
                                    low.data.uv_layers.active.name)),
    "blender_8": (low, material("blender_8", float_image("blender_8", np.round(np.clip(blender_map, 0, 1) * 255) / 255),
                                low.data.uv_layers.active.name)),
}
assign(high, material("plain"))


def render(name, visible):
    for obj in scene.objects:
        if obj.type == "MESH":
            obj.hide_render = obj is not visible
    path = os.path.join(out_dir, "%s_%s.exr" % (shape, name))
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = np.array(image.pixels[:], dtype=np.float64).reshape(resolution, resolution, 4)
    bpy.data.images.remove(image)
    return pixels


reference = render("high", high)
for name, (obj, m) in variants.items():
    assign(obj, m)
    pixels = render(name, obj)
    inside = (reference[:, :, 3] > 0.999) & (pixels[:, :, 3] > 0.999)
    # Premultiplied RGB against black: background pixels compare as black.
    difference = pixels[:, :, :3] - reference[:, :, :3]
    d_in = difference[inside]
    print("RENDER %s %s pixels %d rmse %.6f mean_abs %.6f all_rmse %.6f all_mean_abs %.6f" % (
        shape, name, inside.sum(), np.sqrt((d_in ** 2).mean()), np.abs(d_in).mean(),
        np.sqrt((difference ** 2).mean()), np.abs(difference).mean()))
