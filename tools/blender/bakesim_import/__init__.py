"""bakesim run importer for Blender (3.4 and later).

Install: Edit > Preferences > Add-ons > Install... and pick bakesim_import.zip
(`python3 tools/blender/make_addon.py OUT_DIR` makes it), then tick "Import-Export:
bakesim run". Use: File > Import > bakesim run (choose the run directory), or
from Python: bpy.ops.import_scene.bakesim_run(directory="out/bread-roll").
Without installing: blender --python tools/blender/bakesim_import/__init__.py -- RUN_DIR

What it builds from RUN_DIR (after `bakesim mesh RUN_DIR`):
  * an empty named after the run, turned from bakesim's y-up to Blender's z-up;
  * one object per body sequence ("NAME_bodies") whose mesh is swapped on every
    frame change to meshes/NNNNN.ply of that frame (bakesim frame N shows on
    Blender frame N + 1), with the material "bakesim_baking": its colour ramp
    reads the mesh's U coordinate (thesis Eq 4.5-4.7: 0.15 + 0.8 x the colouring
    quantity, browning by default) through the UV map the PLY carries; where the
    scene's materials give their own raw colours (chocolate, fruit),
    "bakesim_food_colours" shows the PLY's vertex colours instead (bakesim
    browns each food from its own colour);
  * the colliders of meshes/colliders/: NAME.ply as a still object, NAME-NNNNN.ply
    as an object swapped per frame like the bodies, each with a material for the
    look scene.json gives it (metal, ceramic, glass, wood, stone);
  * the scene's frame rate (scene.json time.fps) and frame range.
The frame-change handler is saved with the .blend file only while this add-on is
enabled; bake the sequence (Object > Apply) before sending the file elsewhere.
"""
import json
import math
import os
import re

import bpy
from bpy.app.handlers import persistent
from bpy.props import StringProperty

bl_info = {
    "name": "bakesim run",
    "author": "bakesim",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > bakesim run",
    "description": "Import a bakesim run directory: animated surface meshes, colliders, frame rate, browning material",
    "category": "Import-Export",
}

SEQUENCE_KEY = "bakesim_sequence"  # object property: JSON {blender frame: mesh name}

# The baking palette of src/surface/surface.cpp (palette_colour): sRGB of the
# measured crust colour (src/surface/crust_colour.hpp) at browning 0, 0.1, ..., 1,
# placed at the mesh's U of dough at that browning (U = 0.15 + 0.8 B, Eq 4.7).
# Written out here because Blender cannot call the library; the unit test
# CrustColour.TheBlenderAddOnRampIsTheLibrarysPalette keeps the two equal.
BAKING_STOPS = [(0.15, (0.827, 0.774, 0.647)), (0.23, (0.784, 0.719, 0.585)), (0.31, (0.741, 0.665, 0.525)),
                (0.39, (0.698, 0.611, 0.466)), (0.47, (0.656, 0.557, 0.411)), (0.55, (0.615, 0.503, 0.358)),
                (0.63, (0.573, 0.451, 0.305)), (0.71, (0.531, 0.400, 0.254)), (0.79, (0.489, 0.349, 0.204)),
                (0.87, (0.447, 0.300, 0.155)), (0.95, (0.404, 0.252, 0.107))]


def _linear(c):
    """sRGB components to the linear RGBA Blender's colour ramp holds (IEC 61966-2-1)."""
    return tuple(v / 12.92 if v <= 0.04045 else ((v + 0.055) / 1.055) ** 2.4 for v in c) + (1.0,)


def _import_ply(path):
    """Imports one PLY, returns its mesh datablock and removes the object the importer made."""
    before = set(bpy.data.objects)
    try:  # Blender 3.6+/4.x (operator look-ups are lazy: only calling tells)
        bpy.ops.wm.ply_import(filepath=path)
    except AttributeError:  # Blender <= 3.5
        bpy.ops.import_mesh.ply(filepath=path)
    new = [o for o in bpy.data.objects if o not in before]
    if not new:
        raise RuntimeError(f"bakesim: {path} could not be imported")
    mesh = new[0].data
    for o in new:
        bpy.data.objects.remove(o)
    return mesh


def _body_material(name):
    """The material `name` reduced to its Principled BSDF and output (rebuilt on each import): (mat, bsdf)."""
    mat = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    mat.use_nodes = True
    for n in list(mat.node_tree.nodes):
        if n.type not in ("BSDF_PRINCIPLED", "OUTPUT_MATERIAL"):
            mat.node_tree.nodes.remove(n)
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Roughness"].default_value = 0.75
    return mat, bsdf


def _baking_material():
    mat, bsdf = _body_material("bakesim_baking")
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    uv = nodes.new("ShaderNodeUVMap")
    split = nodes.new("ShaderNodeSeparateXYZ")
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.name = "bakesim_ramp"
    elements = ramp.color_ramp.elements
    while len(elements) > 1:
        elements.remove(elements[-1])
    elements[0].position, elements[0].color = BAKING_STOPS[0][0], _linear(BAKING_STOPS[0][1])
    for at, colour in BAKING_STOPS[1:]:
        elements.new(at).color = _linear(colour)
    links.new(uv.outputs["UV"], split.inputs[0])
    links.new(split.outputs["X"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def _colour_attribute_name(mesh):
    """The name of the vertex colour layer Blender's PLY importer made from the PLY's colours, or None."""
    attributes = getattr(mesh, "color_attributes", None)  # Blender 3.2+
    if attributes is not None and len(attributes) > 0:
        return attributes[0].name
    layers = getattr(mesh, "vertex_colors", None)
    return layers[0].name if layers else None


def _food_colour_material(layer):
    """Foods with their own raw colours (a material's raw_colour: chocolate, fruit): the dough's ramp would
    draw them as dough, so the material shows the PLY's vertex colours, which bakesim computed per food."""
    mat, bsdf = _body_material("bakesim_food_colours")
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    colour = nodes.new("ShaderNodeVertexColor")
    colour.name = "bakesim_vertex_colours"
    colour.layer_name = layer
    links.new(colour.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def _look_material(look):
    name = f"bakesim_{look}"
    mat = bpy.data.materials.get(name)
    if mat:
        return mat
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    # The colours mirror look_albedo (src/geometry/colliders.cpp), linear RGB.
    colour, metallic, roughness, transmission = {
        "metal": ((0.42, 0.43, 0.45), 1.0, 0.35, 0.0),
        "ceramic": ((0.80, 0.78, 0.72), 0.0, 0.15, 0.0),
        "glass": ((0.95, 0.98, 0.98), 0.0, 0.02, 1.0),
        "wood": ((0.42, 0.25, 0.12), 0.0, 0.6, 0.0),
        "stone": ((0.16, 0.15, 0.14), 0.0, 0.8, 0.0),
    }.get(look, ((0.5, 0.5, 0.5), 0.0, 0.5, 0.0))
    bsdf.inputs["Base Color"].default_value = colour + (1.0,)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    for key in ("Transmission", "Transmission Weight"):  # renamed in Blender 4
        if key in bsdf.inputs:
            bsdf.inputs[key].default_value = transmission
    return mat


def _file_name(name):
    """bakesim's output_component: a collider's name as its file name."""
    out = re.sub(r"[^A-Za-z0-9_.-]", "_", name).lstrip(".")[:100]
    return out or "scene"


def _sequence_object(name, meshes_by_frame, material, parent):
    """One object showing meshes_by_frame[frame] (the nearest earlier frame's before it)."""
    first = meshes_by_frame[min(meshes_by_frame)]
    obj = bpy.data.objects.new(name, first)
    obj[SEQUENCE_KEY] = json.dumps({str(f): m.name for f, m in meshes_by_frame.items()})
    for mesh in meshes_by_frame.values():
        mesh.materials.clear()
        mesh.materials.append(material)
        mesh.use_fake_user = True  # kept in the file while another frame is shown
    obj.parent = parent
    bpy.context.scene.collection.objects.link(obj)
    return obj


@persistent
def bakesim_frame_change(scene, *args):
    """Swaps each bakesim sequence object's mesh to the current frame's."""
    frame = scene.frame_current
    for obj in scene.objects:
        table = obj.get(SEQUENCE_KEY)
        if not table:
            continue
        frames = json.loads(table)
        shown = max((int(f) for f in frames if int(f) <= frame), default=min(int(f) for f in frames))
        mesh = bpy.data.meshes.get(frames[str(shown)])
        if mesh is not None and obj.data is not mesh:
            obj.data = mesh


def import_run(run_dir):
    run_dir = os.path.normpath(bpy.path.abspath(run_dir))
    meshes_dir = os.path.join(run_dir, "meshes")
    files = sorted(f for f in os.listdir(meshes_dir) if re.fullmatch(r"\d{5}\.ply", f)) \
        if os.path.isdir(meshes_dir) else []
    if not files:
        raise RuntimeError(f"{meshes_dir}: no NNNNN.ply meshes (run `bakesim mesh {run_dir}` first)")
    with open(os.path.join(run_dir, "scene.json")) as f:
        scene_doc = json.load(f)
    name = scene_doc.get("name") or os.path.basename(run_dir)
    scene = bpy.context.scene
    fps = float(scene_doc.get("time", {}).get("fps", 30.0))
    scene.render.fps = max(1, round(fps))
    scene.render.fps_base = scene.render.fps / fps
    root = bpy.data.objects.new(name, None)
    root.rotation_euler = (math.pi / 2, 0, 0)  # bakesim is y-up, Blender z-up
    scene.collection.objects.link(root)
    bodies = {int(f[:5]) + 1: _import_ply(os.path.join(meshes_dir, f)) for f in files}
    for frame, mesh in bodies.items():
        mesh.name = f"{name}_{frame - 1:05d}"
    material = _baking_material()
    own_colours = any(isinstance(m, dict) and m.get("raw_colour") for m in scene_doc.get("materials", {}).values())
    layer = _colour_attribute_name(bodies[min(bodies)])
    if own_colours and layer:
        material = _food_colour_material(layer)
    _sequence_object(f"{name}_bodies", bodies, material, root)
    looks = {_file_name(c["name"]): c.get("look", "auto") for c in scene_doc.get("colliders", [])}
    shapes = {_file_name(c["name"]): c.get("shape", {}).get("type") for c in scene_doc.get("colliders", [])}
    colliders_dir = os.path.join(meshes_dir, "colliders")
    imported = []
    if os.path.isdir(colliders_dir):
        moving = {}
        for f in sorted(os.listdir(colliders_dir)):
            m = re.fullmatch(r"(.+)-(\d{5})\.ply", f)
            if m and m.group(1) in looks:
                moving.setdefault(m.group(1), {})[int(m.group(2)) + 1] = os.path.join(colliders_dir, f)
        for f in sorted(os.listdir(colliders_dir)):
            stem = f[:-4]
            if f.endswith(".ply") and stem in looks and stem not in moving:
                moving[stem] = {scene.frame_start: os.path.join(colliders_dir, f)}
        for stem, by_frame in moving.items():
            look = looks[stem]
            if look == "auto":  # as bakesim's default_look
                look = {"plane": "wood", "cylinder": "wood", "mesh": "ceramic"}.get(shapes.get(stem), "metal")
            meshes = {frame: _import_ply(path) for frame, path in by_frame.items()}
            for frame, mesh in meshes.items():
                mesh.name = f"{name}_{stem}_{frame - 1:05d}"
            imported.append(_sequence_object(f"{name}_{stem}", meshes, _look_material(look), root))
    scene.frame_start = min(bodies)
    scene.frame_end = max(bodies)
    if bakesim_frame_change not in bpy.app.handlers.frame_change_pre:
        bpy.app.handlers.frame_change_pre.append(bakesim_frame_change)
    scene.frame_set(scene.frame_start)
    return root, imported


class IMPORT_SCENE_OT_bakesim_run(bpy.types.Operator):
    """Import a bakesim run directory (surface meshes, colliders, frame rate)"""
    bl_idname = "import_scene.bakesim_run"
    bl_label = "Import bakesim run"
    bl_options = {"REGISTER", "UNDO"}

    directory: StringProperty(name="Run directory", subtype="DIR_PATH")

    def execute(self, context):
        try:
            root, colliders = import_run(self.directory)
        except (OSError, RuntimeError, ValueError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, f"bakesim: imported {root.name} with {len(colliders)} colliders")
        return {"FINISHED"}

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}


def _menu(self, context):
    self.layout.operator(IMPORT_SCENE_OT_bakesim_run.bl_idname, text="bakesim run")


def register():
    bpy.utils.register_class(IMPORT_SCENE_OT_bakesim_run)
    bpy.types.TOPBAR_MT_file_import.append(_menu)
    if bakesim_frame_change not in bpy.app.handlers.frame_change_pre:
        bpy.app.handlers.frame_change_pre.append(bakesim_frame_change)


def unregister():
    if bakesim_frame_change in bpy.app.handlers.frame_change_pre:
        bpy.app.handlers.frame_change_pre.remove(bakesim_frame_change)
    bpy.types.TOPBAR_MT_file_import.remove(_menu)
    bpy.utils.unregister_class(IMPORT_SCENE_OT_bakesim_run)


if __name__ == "__main__":  # blender --python .../__init__.py -- RUN_DIR
    import sys
    register()
    import_run(sys.argv[sys.argv.index("--") + 1])
