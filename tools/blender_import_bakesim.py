"""Import a bakesim run's surface meshes into Blender as one animated object.

Usage (Blender 3.x or 4.x):
    blender --python tools/blender_import_bakesim.py -- out/bread-roll
or from Blender's Text Editor: set RUN_DIR below and press Run Script.

Every meshes/NNNNN.ply of the run becomes a child of an empty named after the
run, shown only on its own frame (frame NNNNN + 1), with a material that
shows the mesh's vertex colours (the browning colours bakesim computed).
Written against Blender's documented Python API; it has not been run in
bakesim's CI (see docs/surfaces.md).
"""
import math
import os
import re
import sys

import bpy

RUN_DIR = ""  # set here when running from the Text Editor


def run_dir_from_argv():
    if "--" in sys.argv:
        args = sys.argv[sys.argv.index("--") + 1:]
        if args:
            return args[0]
    return RUN_DIR


def import_ply(path):
    """Imports one PLY and returns the new object (both importer generations)."""
    before = set(bpy.data.objects)
    try:  # Blender 3.6+/4.x (operator look-ups are lazy: only calling tells)
        bpy.ops.wm.ply_import(filepath=path)
    except AttributeError:  # Blender ≤ 3.5
        bpy.ops.import_mesh.ply(filepath=path)
    new = [o for o in bpy.data.objects if o not in before]
    return new[0] if new else None


def vertex_colour_material(name):
    mat = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    bsdf = nodes.get("Principled BSDF")
    attr = nodes.new("ShaderNodeVertexColor")
    links.new(attr.outputs["Color"], bsdf.inputs["Base Color"])
    bsdf.inputs["Roughness"].default_value = 0.8
    return mat


def key_visibility(obj, frame):
    for f, hidden in ((frame - 1, True), (frame, False), (frame + 1, True)):
        obj.hide_viewport = hidden
        obj.hide_render = hidden
        obj.keyframe_insert("hide_viewport", frame=f)
        obj.keyframe_insert("hide_render", frame=f)


def main():
    run = run_dir_from_argv()
    meshes = os.path.join(run, "meshes")
    if not os.path.isdir(meshes):
        raise SystemExit(f"{meshes}: no meshes (run `bakesim mesh {run}` first)")
    files = sorted(f for f in os.listdir(meshes) if re.fullmatch(r"\d{5}\.ply", f))
    if not files:
        raise SystemExit(f"{meshes}: no NNNNN.ply files")
    root = bpy.data.objects.new(os.path.basename(os.path.normpath(run)), None)
    root.rotation_euler = (math.pi / 2, 0, 0)  # bakesim is y-up, Blender z-up
    bpy.context.scene.collection.objects.link(root)
    material = vertex_colour_material("bakesim_vertex_colours")
    for name in files:
        frame = int(name[:5]) + 1
        obj = import_ply(os.path.join(meshes, name))
        if obj is None:
            continue
        obj.name = f"{root.name}_{name[:5]}"
        obj.parent = root
        obj.data.materials.clear()
        obj.data.materials.append(material)
        key_visibility(obj, frame)
    scene = bpy.context.scene
    scene.frame_start = int(files[0][:5]) + 1
    scene.frame_end = int(files[-1][:5]) + 1
    print(f"bakesim: imported {len(files)} meshes from {meshes}")


main()
