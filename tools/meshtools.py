"""Small helpers shared by the mesh generators in tools/."""


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
