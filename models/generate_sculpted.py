#!/usr/bin/env python3
"""Mesh-heavy variants of the project's robots, as makers publish theirs.

    python3 models/generate_sculpted.py

Writes models/dual_arm_sculpted.urdf, models/arm7_sculpted.urdf, their
scenes (models/scene_sculpted.yaml, models/arm7_sculpted_scene.yaml: the
primitive robots' scenes with the URDF swapped) and the binary STL files
under models/meshes/sculpted/ (python3 standard library only; two runs give
byte-identical files), reads them back and checks them (every mesh closed
and wound outwards, at least 20 000 visual triangles per arm); exits 1
naming the failed check.

Each URDF is its primitive twin (dual_arm.urdf, arm7.urdf: the same links,
joints, names, origins, limits and inertials) with every box, cylinder and
sphere, visual and collision, replaced by a finely tessellated, sculpted
mesh of about the same shape: cylinders become surfaces of revolution with
filleted ends, a waist and shallow flutes; spheres gain shallow lobes; boxes
get rounded edges. Smooth CAD-like surfaces tessellated far below a
millimetre, as a maker's meshes are (100 000 triangles and more per arm):
what the tracker must simplify to draw in real time, and what the simulator
renders in full (docs/performance.md, "Meshes").
"""

import math
import os
import re
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
MESH_DIR = os.path.join(HERE, "meshes", "sculpted")
PACKAGE = "package://arttrack_models/meshes/sculpted/"

# Tessellation: around the axis, and along a cylinder's side.
AROUND = 96
ALONG = 24
FILLET_STEPS = 8
CAP_RINGS = 6
SPHERE_BANDS = 48
BOX_GRID = 24
# Largest edge radius of a box (m).
BOX_FILLET_MAX = 0.005


def fmt(x):
    return ("%.4f" % x).rstrip("0").rstrip(".")


# --- shapes: (vertices, triangles) with triangles counter-clockwise seen from outside


def revolution(profile, around):
    """A closed surface of revolution about z. `profile`: (rho, z) from the
    bottom pole (rho 0) to the top pole (rho 0), rho > 0 in between."""
    verts, tris = [], []
    bottom = len(verts)
    verts.append((0.0, 0.0, profile[0][1]))
    rings = []
    for rho, z, in profile[1:-1]:
        ring = len(verts)
        for k in range(around):
            a = 2 * math.pi * k / around
            verts.append((rho * math.cos(a), rho * math.sin(a), z))
        rings.append(ring)
    top = len(verts)
    verts.append((0.0, 0.0, profile[-1][1]))
    first = rings[0]
    for k in range(around):  # bottom fan, facing -z
        tris.append((bottom, first + (k + 1) % around, first + k))
    for r0, r1 in zip(rings, rings[1:]):
        for k in range(around):
            k1 = (k + 1) % around
            tris.append((r0 + k, r0 + k1, r1 + k1))
            tris.append((r0 + k, r1 + k1, r1 + k))
    last = rings[-1]
    for k in range(around):  # top fan, facing +z
        tris.append((top, last + k, last + (k + 1) % around))
    return verts, tris


def cylinder(radius, length):
    """Cylinder along z centred at the origin: flat caps, filleted rims, a
    slight waist along the side."""
    f = 0.2 * min(radius, 0.5 * length)
    h = 0.5 * length
    prof = [(0.0, -h)]
    for i in range(1, CAP_RINGS + 1):
        prof.append(((radius - f) * i / CAP_RINGS, -h))
    for i in range(1, FILLET_STEPS):
        a = -0.5 * math.pi + 0.5 * math.pi * i / FILLET_STEPS
        prof.append((radius - f + f * math.cos(a), -h + f + f * math.sin(a)))
    for i in range(ALONG + 1):
        z = -h + f + (length - 2 * f) * i / ALONG
        s = (z + h - f) / (length - 2 * f)  # 0..1 along the side
        waist = 1 - 0.04 * math.sin(math.pi * s) ** 2
        prof.append((radius * waist, z))
    for i in range(1, FILLET_STEPS):
        a = 0.5 * math.pi * i / FILLET_STEPS
        prof.append((radius - f + f * math.cos(a), h - f + f * math.sin(a)))
    for i in range(CAP_RINGS, 0, -1):
        prof.append(((radius - f) * i / CAP_RINGS, h))
    prof.append((0.0, h))
    verts, tris = revolution(prof, AROUND)
    # Shallow flutes: eight grooves along the side, 1.5% of the radius deep.
    out = []
    for x, y, z in verts:
        rho = math.hypot(x, y)
        if rho > radius - f and abs(z) < h - f:
            a = math.atan2(y, x)
            scale = 1 - 0.015 * max(0.0, math.cos(8 * a)) ** 4
            x, y = x * scale, y * scale
        out.append((x, y, z))
    return out, tris


def sphere(radius):
    """Sphere at the origin with four shallow lobes (2% of the radius)."""
    prof = [(0.0, -radius)]
    for i in range(1, SPHERE_BANDS):
        p = math.pi * i / SPHERE_BANDS - 0.5 * math.pi
        prof.append((radius * math.cos(p), radius * math.sin(p)))
    prof.append((0.0, radius))
    verts, tris = revolution(prof, AROUND)
    out = []
    for x, y, z in verts:
        a = math.atan2(y, x)
        p = math.asin(max(-1.0, min(1.0, z / radius)))
        s = 1 + 0.02 * math.cos(4 * a) * math.cos(p) ** 2
        out.append((x * s, y * s, z * s))
    return out, tris


def box(size):
    """Box centred at the origin with rounded edges and corners (radius a
    fifth of its smallest half size, at most BOX_FILLET_MAX: the torso's
    edges would otherwise round off 3 cm and shrink its silhouette in the
    head camera by as much): a subdivided cube pushed onto it."""
    half = [0.5 * s for s in size]
    f = min(0.2 * min(half), BOX_FILLET_MAX)
    inner = [hh - f for hh in half]
    n = BOX_GRID
    verts, tris, index = [], [], {}

    def vertex(c):
        if c not in index:
            q = [c[i] / n * 2 - 1 for i in range(3)]  # on the cube [-1, 1]^3
            p = [q[i] * half[i] for i in range(3)]
            cl = [max(-inner[i], min(inner[i], p[i])) for i in range(3)]
            d = [p[i] - cl[i] for i in range(3)]
            dn = math.sqrt(sum(v * v for v in d))
            if dn > 0:
                p = [cl[i] + f * d[i] / dn for i in range(3)]
            index[c] = len(verts)
            verts.append(tuple(p))
        return index[c]

    # Each face: axis, side (+1/-1); grid over the two other axes, wound outwards.
    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3
        for side in (0, n):
            for i in range(n):
                for j in range(n):
                    def c(a, b):
                        t = [0, 0, 0]
                        t[axis], t[u], t[v] = side, a, b
                        return vertex(tuple(t))
                    a0, a1 = c(i, j), c(i + 1, j)
                    b0, b1 = c(i, j + 1), c(i + 1, j + 1)
                    if side == n:
                        tris += [(a0, a1, b1), (a0, b1, b0)]
                    else:
                        tris += [(a0, b1, a1), (a0, b0, b1)]
    return verts, tris


# --- files


def write_stl(path, verts, tris):
    data = [struct.pack("<80sI", b"arttrack generate_sculpted.py", len(tris))]
    for t in tris:
        a, b, c = (verts[i] for i in t)
        u = [b[k] - a[k] for k in range(3)]
        w = [c[k] - a[k] for k in range(3)]
        nrm = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        ln = math.sqrt(sum(x * x for x in nrm)) or 1.0
        data.append(struct.pack("<12fH", *(x / ln for x in nrm), *a, *b, *c, 0))
    blob = b"".join(data)
    with open(path, "wb") as fh:
        fh.write(blob)


def read_stl(path):
    with open(path, "rb") as fh:
        blob = fh.read()
    (count,) = struct.unpack_from("<I", blob, 80)
    if len(blob) != 84 + 50 * count:
        raise ValueError("%s: size %d does not hold %d triangles" % (path, len(blob), count))
    verts, index, tris = [], {}, []
    for t in range(count):
        vals = struct.unpack_from("<12f", blob, 84 + 50 * t)
        tri = []
        for k in range(3):
            p = vals[3 + 3 * k:6 + 3 * k]
            if p not in index:
                index[p] = len(verts)
                verts.append(p)
            tri.append(index[p])
        tris.append(tuple(tri))
    return verts, tris


def check_closed(path, verts, tris):
    """Every directed edge once and its reverse once; positive volume."""
    edges = {}
    for a, b, c in tris:
        for e in ((a, b), (b, c), (c, a)):
            edges[e] = edges.get(e, 0) + 1
    for (a, b), n in edges.items():
        if n != 1 or edges.get((b, a)) != 1:
            return "%s: edge %d-%d is not shared by exactly two triangles in opposite directions" % (
                path, a, b)
    vol = 0.0
    for a, b, c in tris:
        pa, pb, pc = verts[a], verts[b], verts[c]
        vol += (pa[0] * (pb[1] * pc[2] - pb[2] * pc[1]) - pa[1] * (pb[0] * pc[2] - pb[2] * pc[0]) +
                pa[2] * (pb[0] * pc[1] - pb[1] * pc[0])) / 6
    if not vol > 0:
        return "%s: volume %g is not positive (triangles wound inwards?)" % (path, vol)
    return None


GEOMETRY = re.compile(r"<(cylinder|sphere|box)\s+([^/>]*)/>")


def attr(text, name):
    m = re.search(r'%s="([^"]*)"' % name, text)
    return m.group(1)


def sculpt_urdf(source, target, meshes):
    """Rewrites every primitive of `source` as a sculpted mesh; returns
    per-link triangle counts of the visuals."""
    with open(os.path.join(HERE, source)) as fh:
        text = fh.read()

    def replace(m):
        kind, attrs = m.group(1), m.group(2)
        if kind == "cylinder":
            r, l = float(attr(attrs, "radius")), float(attr(attrs, "length"))
            name = "cylinder_r%s_l%s.stl" % (fmt(r), fmt(l))
            make = lambda: cylinder(r, l)
        elif kind == "sphere":
            r = float(attr(attrs, "radius"))
            name = "sphere_r%s.stl" % fmt(r)
            make = lambda: sphere(r)
        else:
            s = [float(x) for x in attr(attrs, "size").split()]
            name = "box_%s.stl" % "x".join(fmt(x) for x in s)
            make = lambda: box(s)
        if name not in meshes:
            meshes[name] = make()
        return '<mesh filename="%s%s"/>' % (PACKAGE, name)

    out = GEOMETRY.sub(replace, text)
    out = out.replace("<robot name=\"", "<robot name=\"sculpted_", 1)
    header = ("<!-- GENERATED by models/generate_sculpted.py from %s: the same robot with "
              "every primitive a sculpted, finely tessellated mesh. Do not edit. -->\n" % source)
    out = re.sub(r"(<\?xml[^>]*\?>\n)?", lambda m: (m.group(0) or "") + header, out, count=1)
    with open(os.path.join(HERE, target), "w") as fh:
        fh.write(out)
    counts = {}
    for link in re.finditer(r'<link name="([^"]+)"(.*?)</link>', out, re.S):
        n = 0
        for vis in re.finditer(r"<visual>(.*?)</visual>", link.group(2), re.S):
            mm = re.search(r'filename="%s([^"]+)"' % re.escape(PACKAGE), vis.group(1))
            if mm:
                n += len(meshes[mm.group(1)][1])
        if n:
            counts[link.group(1)] = n
    return counts


def sculpt_scene(source, target, urdf_from, urdf_to):
    with open(os.path.join(HERE, source)) as fh:
        text = fh.read()
    line = "  urdf: %s\n" % urdf_from
    if line not in text:
        raise SystemExit("%s: no line '%s'" % (source, line.strip()))
    new_line = "  urdf: %s\n" % urdf_to
    if "  packages:" not in text:  # the meshes' package://arttrack_models/...
        new_line += "  packages: {arttrack_models: .}\n"
    text = text.replace(line, new_line, 1)
    header = ("# GENERATED by models/generate_sculpted.py from %s: the same scene with the "
              "robot's\n# sculpted, mesh-heavy twin (%s). Do not edit.\n" % (source, urdf_to))
    with open(os.path.join(HERE, target), "w") as fh:
        fh.write(header + text)


def main():
    os.makedirs(MESH_DIR, exist_ok=True)
    sculpt_scene("scene_default.yaml", "scene_sculpted.yaml", "dual_arm.urdf",
                 "dual_arm_sculpted.urdf")
    sculpt_scene("arm7_scene.yaml", "arm7_sculpted_scene.yaml", "arm7.urdf", "arm7_sculpted.urdf")
    meshes = {}
    counts = {
        "dual_arm_sculpted.urdf": sculpt_urdf("dual_arm.urdf", "dual_arm_sculpted.urdf", meshes),
        "arm7_sculpted.urdf": sculpt_urdf("arm7.urdf", "arm7_sculpted.urdf", meshes),
    }
    for name in sorted(os.listdir(MESH_DIR)):
        if name not in meshes:
            os.remove(os.path.join(MESH_DIR, name))
    for name, (verts, tris) in sorted(meshes.items()):
        write_stl(os.path.join(MESH_DIR, name), verts, tris)
    failed = []
    for name, (verts, tris) in sorted(meshes.items()):
        path = os.path.join(MESH_DIR, name)
        rv, rt = read_stl(path)
        if len(rt) != len(tris):
            failed.append("%s: read %d triangles, wrote %d" % (path, len(rt), len(tris)))
        why = check_closed(path, rv, rt)
        if why:
            failed.append(why)
    for urdf, per_link in counts.items():
        for arm in ("left_arm", "right_arm", "arm7"):
            n = sum(v for k, v in per_link.items() if k.startswith(arm) or
                    (arm != "arm7" and k.startswith(arm.split("_")[0] + "_hand")))
            if n and n < 20000:
                failed.append("%s: %s has %d visual triangles (expected at least 20 000)" %
                              (urdf, arm, n))
    for urdf, per_link in counts.items():
        print("%s: %d visual triangles" % (urdf, sum(per_link.values())))
        for link, n in per_link.items():
            print("  %-24s %6d" % (link, n))
    print("%d mesh files in %s" % (len(meshes), os.path.relpath(MESH_DIR, HERE)))
    if failed:
        for f in failed:
            print("check failed: " + f, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
