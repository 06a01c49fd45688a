"""Small helpers shared by the mesh generators in tools/."""
import math


def signed_volume(verts, faces):
    """Signed volume of a closed triangle mesh (positive when outward-oriented)."""
    vol = 0.0
    for a, b, c in faces:
        p, q, s = verts[a], verts[b], verts[c]
        vol += (p[0] * (q[1] * s[2] - q[2] * s[1]) - p[1] * (q[0] * s[2] - q[2] * s[0])
                + p[2] * (q[0] * s[1] - q[1] * s[0])) / 6.0
    return vol


def orient_outward(verts, faces):
    """Returns the faces flipped if needed so the mesh is outward-oriented, and its volume."""
    vol = signed_volume(verts, faces)
    if vol < 0:
        faces = [(a, c, b) for a, b, c in faces]
    return faces, abs(vol)


def write_obj(path, verts, faces, comment):
    with open(path, "w") as out:
        out.write("# %s\n" % comment)
        for v in verts:
            out.write("v %.6f %.6f %.6f\n" % v)
        for f in faces:
            out.write("f %d %d %d\n" % tuple(i + 1 for i in f))


def revolve(profile, segments):
    """Closed solid of revolution about the y axis from a closed profile loop
    of (radius, y) points. Points with radius 0 lie on the axis and become a
    single vertex (fans instead of degenerate quads). Returns verts, faces
    (not yet oriented)."""
    verts, rings = [], []
    for r, y in profile:
        if r == 0.0:
            verts.append((0.0, y, 0.0))
            rings.append([len(verts) - 1] * segments)
        else:
            ring = []
            for k in range(segments):
                a = 2 * math.pi * k / segments
                verts.append((r * math.cos(a), y, r * math.sin(a)))
                ring.append(len(verts) - 1)
            rings.append(ring)
    faces = []
    n = len(rings)
    for i in range(n):
        lo, hi = rings[i], rings[(i + 1) % n]
        for k in range(segments):
            k2 = (k + 1) % segments
            a, b, c, d = lo[k], lo[k2], hi[k2], hi[k]
            for tri in ((a, b, c), (a, c, d)):
                if len(set(tri)) == 3:
                    faces.append(tri)
    return verts, faces


def write_revolved(path, profile, segments, comment, what="volume"):
    """Revolves a closed profile, orients it outward and writes it as OBJ."""
    verts, faces = revolve(profile, segments)
    faces, vol = orient_outward(verts, faces)
    write_obj(path, verts, faces, comment)
    print("%s: %d vertices, %d triangles, %s %.3e m^3" % (path, len(verts), len(faces), what, vol))
