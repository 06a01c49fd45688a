"""Run inside Blender (blender -b --factory-startup --python THIS -- ZIP RUN_DIR CHOCOLATE_RUN_DIR [PNG]):
install and enable the bakesim add-on from its zip as Preferences > Install does,
import a run with its operator and check what it built, then the same body as
chocolate (a material raw_colour) with its vertex colours; with PNG, render the
first run's last frame there with Cycles."""
import json
import os
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
zip_path, run, chocolate_run = args[0], args[1], args[2]
png = args[3] if len(args) > 3 else None
bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
bpy.ops.preferences.addon_enable(module="bakesim_import")
assert hasattr(bpy.ops.import_scene, "bakesim_run"), "the add-on did not register its operator"
result = bpy.ops.import_scene.bakesim_run(directory=run)
assert result == {"FINISHED"}, result

doc = json.load(open(os.path.join(run, "scene.json")))
name = doc["name"]
scene = bpy.context.scene
assert abs(scene.render.fps / scene.render.fps_base - doc["time"]["fps"]) < 1e-6, (scene.render.fps, doc["time"])
frames = sorted(int(f[:5]) for f in os.listdir(os.path.join(run, "meshes")) if f.endswith(".ply"))
assert (scene.frame_start, scene.frame_end) == (frames[0] + 1, frames[-1] + 1), (scene.frame_start, scene.frame_end)
bodies = bpy.data.objects[f"{name}_bodies"]
assert bodies.parent.name == name
for f in frames:  # one object, its mesh swapped to each frame's
    scene.frame_set(f + 1)
    assert bodies.data.name == f"{name}_{f:05d}", (f, bodies.data.name)
    assert len(bodies.data.polygons) > 100
    assert len(bodies.data.uv_layers) > 0, "no UV map for the browning ramp"
material = bodies.data.materials[0]
assert material.name == "bakesim_baking" and "bakesim_ramp" in material.node_tree.nodes
tray = bpy.data.objects[f"{name}_tray"]
paddle = bpy.data.objects[f"{name}_paddle"]
assert tray.data.materials[0].name == "bakesim_wood", tray.data.materials[0].name
assert paddle.data.materials[0].name == "bakesim_metal", paddle.data.materials[0].name
scene.frame_set(frames[0] + 1)
first = [v.co.copy() for v in paddle.data.vertices]
scene.frame_set(frames[-1] + 1)
last = [v.co.copy() for v in paddle.data.vertices]
assert max((a - b).length for a, b in zip(first, last)) > 1e-4, "the moving collider did not move"
assert f"{name}_ghost" not in bpy.data.objects, "a hidden collider was imported"
# A food with its own raw colour: the material shows the PLY's vertex colours, dark for chocolate.
result = bpy.ops.import_scene.bakesim_run(directory=chocolate_run)
assert result == {"FINISHED"}, result
chocolate = bpy.data.objects["blender-check-chocolate_bodies"]
material = chocolate.data.materials[0]
assert material.name == "bakesim_food_colours" and "bakesim_vertex_colours" in material.node_tree.nodes, material.name
attributes = getattr(chocolate.data, "color_attributes", None) or chocolate.data.vertex_colors
values = [c for d in attributes[0].data for c in tuple(d.color)[:3]]
mean = sum(values) / len(values)
assert mean < 0.25, f"chocolate's vertex colours average {mean} (linear), not dark"
assert bodies.data.materials[0].name == "bakesim_baking"  # the dough run keeps the ramp
if png:  # the picture, framed and lit as tools/blender/render_run.py does
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "blender"))
    from render_run import render_framed

    render_framed(bodies, png, resolution=(480, 320), samples=32, offset=(1.6, -2.2, 1.4))
print("blender_check: ok", len(frames), "frames,", len([o for o in bpy.data.objects if o.get("bakesim_sequence")]),
      "sequence objects")
