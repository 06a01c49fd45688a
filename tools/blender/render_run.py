"""Render a run's last frame in Blender through the add-on, as a user would see it.

    bakesim mesh RUN_DIR
    python3 tools/blender/make_addon.py OUT_DIR        # writes OUT_DIR/bakesim_import.zip
    blender -b --factory-startup --python tools/blender/render_run.py -- OUT_DIR/bakesim_import.zip RUN_DIR PNG

Installs and enables the add-on from its zip (Preferences > Install), imports
the run with its operator (bodies, colliders, frame rate, browning ramp),
removes the start-up cube, light and camera, frames the bodies with a camera
from the front right and above, adds a sun and renders the last frame with
Cycles (48 samples, no denoiser: Debian's Blender has none) into PNG.
Set BLENDER_USER_CONFIG and BLENDER_USER_SCRIPTS to a scratch folder to keep
the add-on out of your own Blender configuration.
"""
import json
import os
import sys

import bpy
from mathutils import Vector


def render_framed(bodies, png, resolution=(960, 540), samples=48, offset=(1.2, -1.6, 1.5)):
    """Remove the start-up cube, light and camera, frame `bodies` with a camera
    at `offset` times its size from its centre, add a sun and render the
    current frame with Cycles into `png`."""
    scene = bpy.context.scene
    for default in ("Cube", "Light", "Camera"):  # the factory start-up scene's
        if default in bpy.data.objects:
            bpy.data.objects.remove(bpy.data.objects[default])
    bpy.context.view_layer.update()
    corners = [bodies.matrix_world @ Vector(c) for c in bodies.bound_box]
    centre = sum(corners, Vector()) / 8
    size = max((a - b).length for a in corners for b in corners)
    target = bpy.data.objects.new("target", None)
    target.location = centre
    scene.collection.objects.link(target)
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.location = centre + Vector(offset) * size
    track = camera.constraints.new("TRACK_TO")
    track.target, track.track_axis, track.up_axis = target, "TRACK_NEGATIVE_Z", "UP_Y"
    scene.collection.objects.link(camera)
    scene.camera = camera
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    # Lit so that a face square to the sun shows about its albedo, and drawn with
    # the Standard view transform (sRGB, as the ramp's measured colours are given)
    # rather than Filmic, whose highlight roll-off paled a golden crust to cream.
    sun.data.energy = 1.8
    sun.rotation_euler = (0.6, 0.2, 0.5)
    scene.collection.objects.link(sun)
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.4, 0.43, 0.47, 1)
    scene.render.engine = "CYCLES"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False  # Debian's Blender has no OpenImageDenoise
    scene.view_settings.view_transform = "Standard"
    scene.render.resolution_x, scene.render.resolution_y = resolution
    scene.render.filepath = png
    bpy.ops.render.render(write_still=True)


if __name__ == "__main__":
    zip_path, run, png = sys.argv[sys.argv.index("--") + 1:][:3]
    bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
    bpy.ops.preferences.addon_enable(module="bakesim_import")
    assert bpy.ops.import_scene.bakesim_run(directory=run) == {"FINISHED"}
    scene = bpy.context.scene
    name = json.load(open(os.path.join(run, "scene.json")))["name"]
    scene.frame_set(scene.frame_end)
    render_framed(bpy.data.objects[f"{name}_bodies"], png)
    print("rendered", png, "objects:", ", ".join(sorted(o.name for o in bpy.data.objects)))
