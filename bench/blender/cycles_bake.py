# Run inside Blender: blender -b OUT_DIR/pairs.blend -P cycles_bake.py -- SHAPE SIZE DISTANCE OUT.npy [SPACE]
# Cycles "Selected to Active" normal bake (SPACE: tangent, the default, or object) of <SHAPE>_high onto <SHAPE>_low (CPU, one
# sample per texel, cage extrusion = DISTANCE and max ray distance = 2 x DISTANCE, so that the rays
# search DISTANCE on either side of the low surface, as ours do with a maximum distance DISTANCE).
# Writes the float image (rows top to bottom, RGB = (n + 1) / 2) as .npy and prints the seconds
# bpy.ops.object.bake took, wall and processor time (all threads).
import sys
import time

import bpy
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:]
shape, size, distance, out = args[:4]
space = args[4] if len(args) > 4 else "tangent"
assert space in ("tangent", "object"), space
size, distance = int(size), float(distance)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 1
# Denoising is on in the default scene and, with no denoiser in Debian's build ("No device available
# to denoise on"), it leaves a grey image: off, as it must be for data passes anyway.
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
high, low = bpy.data.objects[shape + "_high"], bpy.data.objects[shape + "_low"]
image = bpy.data.images.new("bake", size, size, float_buffer=True)
image.colorspace_settings.name = "Non-Color"
material = bpy.data.materials.new("bake")
material.use_nodes = True
node = material.node_tree.nodes.new("ShaderNodeTexImage")
node.image = image
material.node_tree.nodes.active = node
low.data.materials.clear()
low.data.materials.append(material)
for obj in bpy.context.view_layer.objects:
    obj.select_set(False)
high.select_set(True)
low.select_set(True)
bpy.context.view_layer.objects.active = low
start, cpu_start = time.time(), time.process_time()
bpy.ops.object.bake(type="NORMAL", normal_space=space.upper(), use_selected_to_active=True, cage_extrusion=distance,
                    max_ray_distance=2 * distance, margin=4, target="IMAGE_TEXTURES")
seconds, cpu_seconds = time.time() - start, time.process_time() - cpu_start
pixels = np.array(image.pixels[:], dtype=np.float32).reshape(size, size, 4)[::-1, :, :3]
np.save(out, pixels)
print("BLENDER_BAKE_SECONDS %.3f" % seconds)
print("BLENDER_BAKE_CPU_SECONDS %.3f" % cpu_seconds)
