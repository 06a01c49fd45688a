"""Run inside Blender: import a run with tools/blender_import_bakesim.py and
check the result (one child per mesh, vertex colours, per-frame visibility)."""
import os
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
importer, run = args[0], args[1]
sys.argv = [sys.argv[0], "--", run]
exec(compile(open(importer).read(), importer, "exec"))

meshes = sorted(f for f in os.listdir(os.path.join(run, "meshes")) if f.endswith(".ply"))
root = bpy.data.objects[os.path.basename(os.path.normpath(run))]
children = sorted(root.children, key=lambda o: o.name)
assert len(children) == len(meshes), (len(children), len(meshes))
for child in children:
    mesh = child.data
    has_colours = len(getattr(mesh, "color_attributes", [])) > 0 or len(getattr(mesh, "vertex_colors", [])) > 0
    assert has_colours, f"{child.name}: no vertex colours"
    assert len(mesh.polygons) > 100, f"{child.name}: {len(mesh.polygons)} faces"
    assert child.material_slots[0].material.name == "bakesim_vertex_colours"
scene = bpy.context.scene
first = children[0]
frame = int(first.name[-5:]) + 1
scene.frame_set(frame)
assert not first.hide_render, "a mesh is hidden on its own frame"
scene.frame_set(frame + 1)
assert first.hide_render, "a mesh shows on the next frame"
print("blender_check: ok", len(children), "meshes")
