#!/usr/bin/env python3
"""Packs the Blender add-on tools/blender/bakesim_import/ into OUT_DIR/bakesim_import.zip
(the file Blender's Preferences > Add-ons > Install... takes)."""
import os
import sys
import zipfile

here = os.path.dirname(os.path.abspath(__file__))
out_dir = sys.argv[1] if len(sys.argv) > 1 else "."
os.makedirs(out_dir, exist_ok=True)
target = os.path.join(out_dir, "bakesim_import.zip")
with zipfile.ZipFile(target + ".tmp", "w", zipfile.ZIP_DEFLATED) as z:
    z.write(os.path.join(here, "bakesim_import", "__init__.py"), "bakesim_import/__init__.py")
os.replace(target + ".tmp", target)
print(target)
