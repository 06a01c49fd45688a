#!/usr/bin/python3
"""Writes scenes/bread-of-the-dead.json (thesis Fig 4.12-4.13): a round loaf
with four bone-shaped strips laid over its dome and a ball on top.

The loaf is a sphere cut flat at the tray. The bones follow the dome: each is
a union of small spheres along a meridian arc (its shaft) with larger spheres
spaced along it (the knuckles), one spacing clear of the loaf so the two
bodies do not overlap when sampled. The bones and the ball are one body (a
union), so their overlaps at the top are allowed."""
import json
import math
import sys

SPACING = 0.0025
R, YC, CUT = 0.042, 0.012, 0.010        # loaf sphere radius, centre height, cut (tray top)
SHAFT, KNUCKLE, BALL = 0.0045, 0.0065, 0.009
GAP = SPACING                            # clearance between loaf and topping


def rnd(v):
    return [round(c, 5) for c in v]


def on_dome(theta, phi, radius):
    """Centre of a sphere of the given radius resting on the dome at polar
    angle theta (from the top) and azimuth phi."""
    d = R + GAP + radius
    return rnd([d * math.sin(theta) * math.cos(phi), YC + d * math.cos(theta), d * math.sin(theta) * math.sin(phi)])


def topping():
    parts = []
    for k in range(4):
        phi = math.pi / 4 + k * math.pi / 2
        steps = 12
        for s in range(steps + 1):
            theta = math.radians(12 + (68 - 12) * s / steps)
            parts.append({"type": "sphere", "center": on_dome(theta, phi, SHAFT), "radius": SHAFT})
        for theta in (30, 50, 68):
            parts.append({"type": "sphere", "center": on_dome(math.radians(theta), phi, KNUCKLE), "radius": KNUCKLE})
    parts.append({"type": "sphere", "center": on_dome(0.0, 0.0, BALL), "radius": BALL})
    return {"type": "union", "shapes": parts}


def main(path):
    # As the default roll's (scenes/bread-roll.json): bubbles vent where they face the oven air, so the
    # skin stays dough and browns.
    bubbles = {"fraction": 0.4, "distribution": "uniform", "pressure_scale": 12000.0, "max_expansion": 2.5,
               "end_temperature": 100.0, "vent_at_surface": True}
    scene = {
        "format": "bakesim-scene/1",
        "name": "bread-of-the-dead",
        "description": ("Bread of the dead (pan de muerto, thesis Fig 4.12-4.13): a round loaf with four bone-shaped "
                        "strips over its dome and a ball on top (written by tools/make_bread_of_the_dead.py). The "
                        "dough is smooth and elastic even raw (mu_e 8000 Pa when cold, rising to 5e4 Pa as it "
                        "sets, Zhang relaxation time), so the bones and the ball keep their shape while the loaf "
                        "rises on a 180 degC tray under 220 degC air. Bake clock 750: 2 s of mechanics are a "
                        "25-minute bake. Water, oven and crust as the default roll's (scenes/bread-roll.json): "
                        "moisture 0.85 kg per kg of dry solid leaving by boiling at the evaporation front "
                        "(environment.mass_transfer_coefficient 0), the oven's walls radiating (emissivity 0.9), "
                        "a dried crust of 0.1 W/(m K), bubbles venting at the surface; so the crumb stops at the "
                        "boiling point while the crust dries and browns."),
        "solver": {"type": "sph",
                   "sph": {"spacing": SPACING, "smoothing_ratio": 2.0, "speed_of_sound": 5.0},
                   "cfl": 0.4, "max_dt": 0.001},
        "time": {"end": 2.0, "fps": 20},
        "domain": {"min": [-0.08, 0.0, -0.08], "max": [0.08, 0.14, 0.08]},
        "gravity": [0.0, -9.81, 0.0],
        "environment": {"air_temperature": 220.0, "heat_transfer_coefficient": 25.0, "bake_time_scale": 750.0,
                        "mass_transfer_coefficient": 0.0, "emissivity": 0.9},
        "materials": {
            "elastic-dough": {
                "preset": "dough",
                "viscosity": {"curve": "piecewise_linear", "points": [[26, 5.0], [120, 50.0]]},
                "elasticity": {"curve": "piecewise_linear", "points": [[26, 8000.0], [45, 8000.0], [120, 50000.0]]},
                "moisture": {"content": 0.85, "gas_fraction": 0.1, "tortuosity": 10, "dry_conductivity": 0.1}
            }
        },
        "bodies": [
            {"name": "loaf", "material": "elastic-dough", "temperature": 26.0,
             "shape": {"type": "difference",
                       "base": {"type": "sphere", "center": [0.0, YC, 0.0], "radius": R},
                       "subtract": [{"type": "box", "min": [-0.1, -0.1, -0.1], "max": [0.1, CUT, 0.1]}]},
             "bubbles": dict(bubbles, seed=1)},
            {"name": "bones-and-ball", "material": "elastic-dough", "temperature": 26.0,
             "shape": topping(), "bubbles": dict(bubbles, seed=2)}
        ],
        "colliders": [
            {"name": "tray", "shape": {"type": "plane", "point": [0.0, CUT - 0.0005, 0.0], "normal": [0, 1, 0]},
             "friction": 0.5, "damping": 1.0, "temperature": 180.0, "heat_transfer_coefficient": 100.0}
        ],
        "probes": [
            {"name": "core", "position": [0.0, YC + 0.012, 0.0], "follow": True, "quantities": ["temperature"]},
            {"name": "ball", "position": on_dome(0.0, 0.0, BALL), "follow": True, "quantities": ["temperature"]}
        ],
        "output": {"particles": ["ply", "vtu"], "every_frames": 1}
    }
    with open(path, "w") as out:
        json.dump(scene, out, indent=2)
        out.write("\n")
    print(path)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "scenes/bread-of-the-dead.json")
