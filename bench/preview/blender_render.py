# Renders a glTF with Blender's Cycles on the CPU, headless, for bench/preview.sh:
#   blender -b --factory-startup --python blender_render.py -- IN.gltf OUT.png SIZE SAMPLES CAMERA.json [ENV.hdr]
# CAMERA.json is the camera gltf-pbr preview used ({"position", "target", "up", "yfovRadians"}), so
# both renderers frame the asset the same way; ENV is the environment it lit the asset with.
import json
import sys

import numpy

# Debian 12's Blender 3.4 glTF importer still uses numpy.bool, removed in numpy 1.24.
numpy.bool = bool

import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402

args = sys.argv[sys.argv.index("--") + 1:]
source, output, size, samples, camera_file = args[0], args[1], int(args[2]), int(args[3]), args[4]
environment = args[5] if len(args) > 5 else None

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=source)

scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False
scene.render.resolution_x = size
scene.render.resolution_y = size
scene.render.film_transparent = False
scene.view_settings.view_transform = "Standard"  # plain sRGB, as our tone-mapped PNG
scene.render.image_settings.file_format = "PNG"
scene.render.image_settings.color_depth = "8"

# glTF is +Y up; Blender's importer turns it into +Z up: (x, y, z) -> (x, -z, y).
def to_blender(v):
    return Vector((v[0], -v[2], v[1]))

camera = json.load(open(camera_file))
data = bpy.data.cameras.new("preview")
data.sensor_fit = "VERTICAL"
data.angle = camera["yfovRadians"]
data.clip_start = camera.get("near", 0.01)
data.clip_end = camera.get("far", 1000.0)
obj = bpy.data.objects.new("preview", data)
scene.collection.objects.link(obj)
position, target = to_blender(camera["position"]), to_blender(camera["target"])
obj.location = position
obj.rotation_euler = (target - position).to_track_quat("-Z", "Y").to_euler()
scene.camera = obj

world = bpy.data.worlds.new("preview")
world.use_nodes = True
scene.world = world
background = world.node_tree.nodes["Background"]
if environment:
    texture = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    texture.image = bpy.data.images.load(environment)
    world.node_tree.links.new(texture.outputs["Color"], background.inputs["Color"])
else:
    background.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)

scene.render.filepath = output
bpy.ops.render.render(write_still=True)
