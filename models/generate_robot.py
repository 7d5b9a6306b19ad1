#!/usr/bin/env python3
"""Generates the arttrack robot description in models/ (this script's folder).

Writes:
  dual_arm.urdf         primitives only (box, cylinder, sphere): the simulator and the tracker
  dual_arm_meshes.urdf  the same kinematics, inertials and names; some links as mesh files
  meshes/...            binary STL, Wavefront OBJ and COLLADA files generated from the
                        same primitives, so both robots look alike

Then it reads the written files back and checks them: URDF structure (visual == collision),
the mesh files (closed, consistently wound, outward, same extent as the primitives), the
home pose (lower arms and hands inside the head camera's image, no link intersecting
another, hands above the table). It prints the check results and exits non-zero on failure.

Standard library only and deterministic: two runs write byte-identical files.
Usage: python3 models/generate_robot.py
"""

import math
import os
import struct
import sys
import xml.etree.ElementTree as ET

MODELS_DIR = os.path.dirname(os.path.abspath(__file__))
PACKAGE_NAME = "arttrack_models"  # package://arttrack_models/ is the models/ folder

# ----------------------------------------------------------------------------------------
# Small linear algebra (3-vectors as lists, 3x3 matrices as lists of rows).


def v_add(a, b):
    return [a[0] + b[0], a[1] + b[1], a[2] + b[2]]


def v_sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def v_scale(a, s):
    return [a[0] * s, a[1] * s, a[2] * s]


def v_dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def v_cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def v_norm(a):
    return math.sqrt(v_dot(a, a))


def v_normalized(a):
    n = v_norm(a)
    return [a[0] / n, a[1] / n, a[2] / n]


def m_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def m_vec(a, v):
    return [a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2] for i in range(3)]


def m_transpose(a):
    return [[a[j][i] for j in range(3)] for i in range(3)]


def m_identity():
    return [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]


def rpy_matrix(rpy):
    """URDF convention: fixed-axis roll about x, then pitch about y, then yaw about z."""
    return m_mul(rot_z(rpy[2]), m_mul(rot_y(rpy[1]), rot_x(rpy[0])))


def axis_angle_matrix(axis, angle):
    x, y, z = v_normalized(axis)
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return [[c + x * x * t, x * y * t - z * s, x * z * t + y * s],
            [y * x * t + z * s, c + y * y * t, y * z * t - x * s],
            [z * x * t - y * s, z * y * t + x * s, c + z * z * t]]


class Pose:
    """Rigid transform T_a_b: maps b coordinates to a coordinates (p_a = R p_b + t)."""

    def __init__(self, rotation=None, translation=None):
        self.R = rotation if rotation is not None else m_identity()
        self.t = list(translation) if translation is not None else [0.0, 0.0, 0.0]

    @staticmethod
    def from_xyz_rpy(xyz, rpy):
        return Pose(rpy_matrix(rpy), xyz)

    def __mul__(self, other):
        return Pose(m_mul(self.R, other.R), v_add(m_vec(self.R, other.t), self.t))

    def apply(self, p):
        return v_add(m_vec(self.R, p), self.t)

    def rotate(self, v):
        return m_vec(self.R, v)

    def inverse(self):
        rt = m_transpose(self.R)
        return Pose(rt, v_scale(m_vec(rt, self.t), -1.0))


# ----------------------------------------------------------------------------------------
# Number formatting (deterministic, no "-0").


def fmt(x, decimals=9):
    s = ("%." + str(decimals) + "f") % x
    s = s.rstrip("0").rstrip(".") if "." in s else s
    return "0" if s in ("-0", "") else s


def fmt_g(x):
    s = "%.9g" % x
    return "0" if s == "-0" else s


def fmt_vec(v, decimals=9):
    return " ".join(fmt(x, decimals) for x in v)


# ----------------------------------------------------------------------------------------
# Primitive shapes. Each lives in its link frame at `xyz`/`rpy` (URDF <origin>); cylinders
# run along their local z and are centred on their origin, as in URDF.


class Shell:
    """A closed polygon mesh: positions, normals, faces as lists of (position, normal)
    index pairs, wound counter-clockwise seen from outside."""

    def __init__(self):
        self.positions = []
        self.normals = []
        self.faces = []

    def transformed(self, pose, scale=1.0):
        out = Shell()
        out.positions = [v_scale(pose.apply(p), scale) for p in self.positions]
        out.normals = [pose.rotate(n) for n in self.normals]
        out.faces = [list(f) for f in self.faces]
        return out

    def triangles(self):
        """Fan-triangulated faces as position triples."""
        tris = []
        for f in self.faces:
            for k in range(1, len(f) - 1):
                tris.append((self.positions[f[0][0]], self.positions[f[k][0]],
                             self.positions[f[k + 1][0]]))
        return tris


class Box:
    kind = "box"

    def __init__(self, size, xyz=(0, 0, 0), rpy=(0, 0, 0), material=None):
        self.size, self.xyz, self.rpy, self.material = list(size), list(xyz), list(rpy), material

    def pose(self):
        return Pose.from_xyz_rpy(self.xyz, self.rpy)

    def volume(self):
        return self.size[0] * self.size[1] * self.size[2]

    def unit_inertia(self):
        a, b, c = self.size
        return [(b * b + c * c) / 12.0, (a * a + c * c) / 12.0, (a * a + b * b) / 12.0]

    def urdf_geometry(self):
        return '<box size="%s"/>' % fmt_vec(self.size)

    def local_sdf(self, p):
        q = [abs(p[i]) - 0.5 * self.size[i] for i in range(3)]
        outside = v_norm([max(x, 0.0) for x in q])
        return outside + min(max(q), 0.0)

    def local_segment_hits(self, o, d):
        """Does the segment o + t d, 0 < t < 1, pass through the solid? (slab test)"""
        t0, t1 = 0.0, 1.0
        for i in range(3):
            h = 0.5 * self.size[i]
            if abs(d[i]) < 1e-12:
                if abs(o[i]) > h:
                    return False
                continue
            a, b = (-h - o[i]) / d[i], (h - o[i]) / d[i]
            t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
            if t0 >= t1:
                return False
        return True

    def local_surface_points(self, n=7):
        pts = []
        h = [0.5 * s for s in self.size]
        for axis in range(3):
            u, w = (axis + 1) % 3, (axis + 2) % 3
            for sign in (-1.0, 1.0):
                for i in range(n):
                    for j in range(n):
                        p = [0.0, 0.0, 0.0]
                        p[axis] = sign * h[axis]
                        p[u] = -h[u] + 2.0 * h[u] * i / (n - 1)
                        p[w] = -h[w] + 2.0 * h[w] * j / (n - 1)
                        pts.append(p)
        return pts

    def local_shell(self):
        s = Shell()
        h = [0.5 * x for x in self.size]
        for axis in range(3):
            u, w = (axis + 1) % 3, (axis + 2) % 3
            for sign in (-1.0, 1.0):
                normal = [0.0, 0.0, 0.0]
                normal[axis] = sign
                s.normals.append(normal)
                ni = len(s.normals) - 1
                corners = []
                # (u, w) square counter-clockwise seen from +axis; reversed for -axis.
                for cu, cw in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                    p = [0.0, 0.0, 0.0]
                    p[axis], p[u], p[w] = sign * h[axis], cu * h[u], cw * h[w]
                    corners.append(p)
                if sign < 0:
                    corners.reverse()
                face = []
                for p in corners:
                    s.positions.append(p)
                    face.append((len(s.positions) - 1, ni))
                s.faces.append(face)
        return weld(s)


class Cylinder:
    kind = "cylinder"
    SEGMENTS = 32

    def __init__(self, radius, length, xyz=(0, 0, 0), rpy=(0, 0, 0), material=None):
        self.radius, self.length = radius, length
        self.xyz, self.rpy, self.material = list(xyz), list(rpy), material

    def pose(self):
        return Pose.from_xyz_rpy(self.xyz, self.rpy)

    def volume(self):
        return math.pi * self.radius ** 2 * self.length

    def unit_inertia(self):
        r, l = self.radius, self.length
        i_xy = (3.0 * r * r + l * l) / 12.0
        return [i_xy, i_xy, 0.5 * r * r]

    def urdf_geometry(self):
        return '<cylinder radius="%s" length="%s"/>' % (fmt(self.radius), fmt(self.length))

    def local_sdf(self, p):
        dr = math.hypot(p[0], p[1]) - self.radius
        dz = abs(p[2]) - 0.5 * self.length
        return min(max(dr, dz), 0.0) + math.hypot(max(dr, 0.0), max(dz, 0.0))

    def local_segment_hits(self, o, d):
        h, r = 0.5 * self.length, self.radius
        t0, t1 = 0.0, 1.0
        if abs(d[2]) < 1e-12:
            if abs(o[2]) > h:
                return False
        else:
            a, b = (-h - o[2]) / d[2], (h - o[2]) / d[2]
            t0, t1 = max(t0, min(a, b)), min(t1, max(a, b))
        qa = d[0] * d[0] + d[1] * d[1]
        qb = 2.0 * (o[0] * d[0] + o[1] * d[1])
        qc = o[0] * o[0] + o[1] * o[1] - r * r
        if qa < 1e-18:
            return qc < 0.0 and t0 < t1
        disc = qb * qb - 4.0 * qa * qc
        if disc <= 0.0:
            return False
        sq = math.sqrt(disc)
        t0, t1 = max(t0, (-qb - sq) / (2.0 * qa)), min(t1, (-qb + sq) / (2.0 * qa))
        return t0 < t1

    def local_surface_points(self, n_around=24, n_along=8):
        pts = []
        h, r = 0.5 * self.length, self.radius
        for i in range(n_around):
            a = 2.0 * math.pi * i / n_around
            c, s = math.cos(a), math.sin(a)
            for j in range(n_along):
                pts.append([r * c, r * s, -h + 2.0 * h * j / (n_along - 1)])
            for z in (-h, h):
                for k in (0.33, 0.66):
                    pts.append([k * r * c, k * r * s, z])
        pts += [[0.0, 0.0, -h], [0.0, 0.0, h]]
        return pts

    def local_shell(self):
        s = Shell()
        n, h, r = self.SEGMENTS, 0.5 * self.length, self.radius
        for i in range(n):
            a = 2.0 * math.pi * i / n
            s.positions.append([r * math.cos(a), r * math.sin(a), -h])
            s.normals.append([math.cos(a), math.sin(a), 0.0])
        for i in range(n):
            a = 2.0 * math.pi * i / n
            s.positions.append([r * math.cos(a), r * math.sin(a), h])
        s.positions += [[0.0, 0.0, -h], [0.0, 0.0, h]]
        bottom_c, top_c = 2 * n, 2 * n + 1
        s.normals += [[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]]
        down, up = n, n + 1
        for i in range(n):
            j = (i + 1) % n
            s.faces.append([(i, i), (j, j), (n + j, j), (n + i, i)])  # side quad
            s.faces.append([(top_c, up), (n + i, up), (n + j, up)])  # top fan
            s.faces.append([(bottom_c, down), (j, down), (i, down)])  # bottom fan
        return s


class Sphere:
    kind = "sphere"
    SLICES, STACKS = 32, 16

    def __init__(self, radius, xyz=(0, 0, 0), material=None):
        self.radius, self.xyz, self.rpy, self.material = radius, list(xyz), [0, 0, 0], material

    def pose(self):
        return Pose.from_xyz_rpy(self.xyz, self.rpy)

    def volume(self):
        return 4.0 / 3.0 * math.pi * self.radius ** 3

    def unit_inertia(self):
        i = 0.4 * self.radius ** 2
        return [i, i, i]

    def urdf_geometry(self):
        return '<sphere radius="%s"/>' % fmt(self.radius)

    def local_sdf(self, p):
        return v_norm(p) - self.radius

    def local_segment_hits(self, o, d):
        t = min(max(-v_dot(o, d) / v_dot(d, d), 0.0), 1.0)
        return v_norm(v_add(o, v_scale(d, t))) < self.radius

    def local_surface_points(self, n=200):
        pts = []
        golden = math.pi * (3.0 - math.sqrt(5.0))
        for i in range(n):
            z = 1.0 - 2.0 * (i + 0.5) / n
            rho = math.sqrt(1.0 - z * z)
            a = golden * i
            pts.append(v_scale([rho * math.cos(a), rho * math.sin(a), z], self.radius))
        return pts

    def local_shell(self):
        s = Shell()
        ns, nt, r = self.SLICES, self.STACKS, self.radius
        s.positions.append([0.0, 0.0, -r])
        s.normals.append([0.0, 0.0, -1.0])
        for k in range(1, nt):
            theta = math.pi * k / nt - 0.5 * math.pi  # latitude, south to north
            for i in range(ns):
                a = 2.0 * math.pi * i / ns
                n = [math.cos(theta) * math.cos(a), math.cos(theta) * math.sin(a), math.sin(theta)]
                s.positions.append(v_scale(n, r))
                s.normals.append(n)
        s.positions.append([0.0, 0.0, r])
        s.normals.append([0.0, 0.0, 1.0])
        south, north = 0, len(s.positions) - 1

        def ring(k, i):  # k = 1 .. nt-1
            return 1 + (k - 1) * ns + (i % ns)

        for i in range(ns):
            a, b = ring(1, i), ring(1, i + 1)
            s.faces.append([(south, south), (b, b), (a, a)])
            a, b = ring(nt - 1, i), ring(nt - 1, i + 1)
            s.faces.append([(north, north), (a, a), (b, b)])
            for k in range(1, nt - 1):
                a, b, c, d = ring(k, i), ring(k, i + 1), ring(k + 1, i + 1), ring(k + 1, i)
                s.faces.append([(a, a), (b, b), (c, c), (d, d)])
        return s


def weld(shell):
    """Merges coincident positions (boxes are built per face) so the shell is indexed."""
    index, positions, remap = {}, [], []
    for p in shell.positions:
        key = tuple(round(x, 12) for x in p)
        if key not in index:
            index[key] = len(positions)
            positions.append(p)
        remap.append(index[key])
    out = Shell()
    out.positions, out.normals = positions, shell.normals
    out.faces = [[(remap[pi], ni) for pi, ni in f] for f in shell.faces]
    return out


def world_shell(shape):
    """The shape's shell in its link frame."""
    return shape.local_shell().transformed(shape.pose())


# ----------------------------------------------------------------------------------------
# The robot. Frames: base_link at the world origin, x forward, y left, z up.

DEG = math.pi / 180.0
SIDES = ("left", "right")

MATERIALS = [
    ("base_grey", (0.30, 0.30, 0.33, 1.0)),
    ("torso_white", (0.85, 0.85, 0.82, 1.0)),
    ("lwr_orange", (1.00, 0.45, 0.05, 1.0)),
    ("joint_grey", (0.55, 0.55, 0.58, 1.0)),
    ("hand_black", (0.12, 0.12, 0.12, 1.0)),
    ("head_blue", (0.20, 0.30, 0.60, 1.0)),
]

# KUKA LWR 4 proportions: offset of joint i+1's origin along link i's z (metres); joint 1
# sits 0.11 above the mount, so mount -> shoulder (joint 2) is 0.31, shoulder -> elbow
# (joint 4) 0.40, elbow -> wrist (joint 6) 0.39, wrist -> flange (joint 7) 0.078.
LWR_OFFSETS_M = [0.11, 0.20, 0.20, 0.20, 0.20, 0.19, 0.078]
LWR_AXES = ["z", "y", "z", "y", "z", "y", "z"]
LWR_LIMITS_DEG = [170, 120, 170, 120, 170, 120, 170]
LWR_EFFORT_NM = [176, 176, 100, 100, 100, 38, 38]
LWR_VELOCITY_DEG_S = [110, 110, 128, 128, 204, 184, 184]
LWR_DAMPING = 0.5  # N m s / rad, a small viscous friction for simulation

# Arm mounts, torso frame (left; the right one is the mirror image): 2 cm outside the torso's
# side face (y = 0.18), 0.30 above the torso's bottom, so 1.10 m above the floor. link_0's z
# (the arm's base axis) points out, forward and up: (0.587, 0.492, 0.643) for the left arm.
ARM_MOUNT_XYZ = (0.0, 0.20, 0.30)
ARM_MOUNT_RPY_DEG = (-50.0, 0.0, -50.0)
HAND_EE_Z = 0.105  # grasp point, between the fingers and the thumb, along the hand's z

# Home configuration (degrees), left arm; the right arm mirrors it (joints 1, 3, 5, 7 flip).
HOME_LEFT_ARM_DEG = [30.0, 65.0, 30.0, 90.0, 30.0, -80.0, 20.0]
HOME_HEAD_DEG = {"head_pan_joint": 0.0, "head_tilt_joint": 40.0}

# The head camera assumed by the checks (an Asus-Xtion-like depth camera).
CAMERA_WIDTH, CAMERA_HEIGHT, CAMERA_FOVY_DEG = 640, 480, 45.0
TABLE_TOP_Z = 0.75


class Link:
    def __init__(self, name, shapes=(), mass=0.0):
        self.name, self.shapes, self.mass = name, list(shapes), mass


class Joint:
    def __init__(self, name, jtype, parent, child, xyz, rpy=(0, 0, 0), axis=None, lower=None,
                 upper=None, effort=None, velocity=None, damping=None):
        self.name, self.type, self.parent, self.child = name, jtype, parent, child
        self.xyz, self.rpy, self.axis = list(xyz), list(rpy), axis
        self.lower, self.upper, self.effort, self.velocity = lower, upper, effort, velocity
        self.damping = damping


def hand_shapes(side):
    """Palm, two fingers on the hand's +y side and a thicker, shorter thumb on -y (mirrored
    for the right hand): no rotation about the approach axis z maps the hand onto itself."""
    s = 1.0 if side == "left" else -1.0
    m = "hand_black"
    return [
        Box((0.05, 0.09, 0.07), (0.0, 0.0, 0.035), material=m),  # palm
        Box((0.016, 0.016, 0.065), (0.016, s * 0.030, 0.1025), material=m),  # finger 1
        Box((0.016, 0.016, 0.065), (-0.016, s * 0.030, 0.1025), material=m),  # finger 2
        Box((0.020, 0.020, 0.050), (0.0, -s * 0.030, 0.095), material=m),  # thumb
    ]


def lwr_link_shapes(i):
    """LWR-like link i (1..7) in its own frame: origin on joint i, joint i+1 on +z. A sphere
    houses each y-axis joint (2, 4, 6), cylinders join them."""
    o, g = "lwr_orange", "joint_grey"
    if i == 1:
        return [Cylinder(0.060, 0.13, (0, 0, 0.065), material=o)]
    if i == 2:
        return [Sphere(0.070, material=g), Cylinder(0.060, 0.17, (0, 0, 0.115), material=o)]
    if i == 3:
        return [Cylinder(0.060, 0.135, (0, 0, 0.0675), material=o)]
    if i == 4:
        return [Sphere(0.065, material=g), Cylinder(0.055, 0.17, (0, 0, 0.115), material=o)]
    if i == 5:
        return [Cylinder(0.055, 0.135, (0, 0, 0.0675), material=o)]
    if i == 6:
        return [Sphere(0.060, material=g), Cylinder(0.045, 0.048, (0, 0, 0.024), material=o)]
    return [Cylinder(0.045, 0.030, (0, 0, -0.015), material=g)]  # 7: flange disc


LWR_MASSES_KG = [2.0, 2.7, 2.7, 2.3, 2.3, 1.6, 1.6, 1.0]  # link 0 (mount) .. 7
HAND_MASS_KG = 1.2


def mirror_rpy(rpy, side):
    """Mirror image in the world's xz plane: roll and yaw change sign."""
    return list(rpy) if side == "left" else [-rpy[0], rpy[1], -rpy[2]]


def mirror_xyz(xyz, side):
    return list(xyz) if side == "left" else [xyz[0], -xyz[1], xyz[2]]


def home_configuration():
    """Joint name -> angle (radians) of the documented home pose."""
    home = {}
    for side in SIDES:
        for i, deg in enumerate(HOME_LEFT_ARM_DEG):
            sign = -1.0 if (side == "right" and LWR_AXES[i] == "z") else 1.0
            home["%s_arm_joint_%d" % (side, i + 1)] = sign * deg * DEG + 0.0  # no -0
    for name, deg in HOME_HEAD_DEG.items():
        home[name] = deg * DEG
    return home


def build_robot():
    """Links and joints in a fixed order (parents before children)."""
    links, joints = [], []
    links.append(Link("base_link", [
        Box((0.50, 0.50, 0.04), (0, 0, 0.02), material="base_grey"),  # floor plate
        Cylinder(0.11, 0.76, (0, 0, 0.42), material="base_grey"),  # pedestal column
    ], 40.0))
    # Torso from 0.80 m to 1.30 m.
    links.append(Link("torso", [Box((0.30, 0.36, 0.50), (0, 0, 0.25), material="torso_white")],
                      20.0))
    joints.append(Joint("torso_joint", "fixed", "base_link", "torso", (0, 0, 0.80)))

    # Head: a neck post at the back of the torso top, a pan-tilt yoke, the camera on the head's
    # front at about 1.65 m: high and far enough back to see the elbows and over the torso.
    links.append(Link("neck_link", [Cylinder(0.04, 0.27, (0, 0, 0.135), material="base_grey")],
                      1.5))
    joints.append(Joint("neck_joint", "fixed", "torso", "neck_link", (-0.11, 0, 0.50)))
    links.append(Link("head_pan_link", [
        Cylinder(0.05, 0.02, (0, 0, 0.01), material="base_grey"),
        Box((0.05, 0.015, 0.14), (0, 0.1075, 0.07), material="base_grey"),
        Box((0.05, 0.015, 0.14), (0, -0.1075, 0.07), material="base_grey"),
    ], 0.6))
    joints.append(Joint("head_pan_joint", "revolute", "neck_link", "head_pan_link", (0, 0, 0.27),
                        axis=(0, 0, 1), lower=-1.6, upper=1.6, effort=10.0, velocity=3.0,
                        damping=0.1))
    # Head box entirely behind the camera origin (x < 0.06): the camera never sees it.
    links.append(Link("head_tilt_link", [
        Box((0.15, 0.18, 0.11), (-0.025, 0, 0), material="head_blue")], 1.2))
    joints.append(Joint("head_tilt_joint", "revolute", "head_pan_link", "head_tilt_link",
                        (0, 0, 0.11), axis=(0, 1, 0), lower=-0.6, upper=1.2, effort=10.0,
                        velocity=3.0, damping=0.1))
    links.append(Link("camera_link"))
    joints.append(Joint("camera_joint", "fixed", "head_tilt_link", "camera_link", (0.06, 0, 0)))
    links.append(Link("camera_optical_frame"))
    joints.append(Joint("camera_optical_joint", "fixed", "camera_link", "camera_optical_frame",
                        (0, 0, 0), (-0.5 * math.pi, 0, -0.5 * math.pi)))

    for side in SIDES:
        prefix = side + "_arm_"
        links.append(Link(prefix + "link_0",
                          [Cylinder(0.07, 0.11, (0, 0, 0.055), material="joint_grey")],
                          LWR_MASSES_KG[0]))
        joints.append(Joint(prefix + "mount_joint", "fixed", "torso", prefix + "link_0",
                            mirror_xyz(ARM_MOUNT_XYZ, side),
                            mirror_rpy([a * DEG for a in ARM_MOUNT_RPY_DEG], side)))
        for i in range(1, 8):
            links.append(Link(prefix + "link_%d" % i, lwr_link_shapes(i), LWR_MASSES_KG[i]))
            axis = (0, 0, 1) if LWR_AXES[i - 1] == "z" else (0, 1, 0)
            lim = LWR_LIMITS_DEG[i - 1] * DEG
            joints.append(Joint(prefix + "joint_%d" % i, "revolute", prefix + "link_%d" % (i - 1),
                                prefix + "link_%d" % i, (0, 0, LWR_OFFSETS_M[i - 1]), axis=axis,
                                lower=-lim, upper=lim, effort=float(LWR_EFFORT_NM[i - 1]),
                                velocity=LWR_VELOCITY_DEG_S[i - 1] * DEG, damping=LWR_DAMPING))
        links.append(Link(side + "_hand", hand_shapes(side), HAND_MASS_KG))
        joints.append(Joint(side + "_hand_joint", "fixed", prefix + "link_7", side + "_hand",
                            (0, 0, 0)))
        links.append(Link(side + "_ee"))
        joints.append(Joint(side + "_ee_joint", "fixed", side + "_hand", side + "_ee",
                            (0, 0, HAND_EE_Z)))
    return links, joints


def link_inertial(link):
    """Mass spread over the link's primitives in proportion to their volumes (overlaps are
    counted twice, which is plausible enough): centre of mass and the inertia tensor about it,
    in the link frame's axes."""
    total_volume = sum(s.volume() for s in link.shapes)
    com = [0.0, 0.0, 0.0]
    for s in link.shapes:
        com = v_add(com, v_scale(s.xyz, s.volume() / total_volume))
    inertia = [[0.0] * 3 for _ in range(3)]
    for s in link.shapes:
        m = link.mass * s.volume() / total_volume
        r = rpy_matrix(s.rpy)
        d = s.unit_inertia()
        local = [[m * d[i] if i == j else 0.0 for j in range(3)] for i in range(3)]
        rotated = m_mul(r, m_mul(local, m_transpose(r)))
        off = v_sub(s.xyz, com)
        dd = v_dot(off, off)
        for i in range(3):
            for j in range(3):
                inertia[i][j] += rotated[i][j] + m * ((dd if i == j else 0.0) - off[i] * off[j])
    return com, inertia


# ----------------------------------------------------------------------------------------
# Mesh variant: which links use which files (every loader case once).


def mesh_assignments():
    """link name -> (URDF filename, scale, kind). Kinds: stl, stl_solid_header, obj, dae."""
    out = {}
    for side in SIDES:
        p = side + "_arm_"
        out[p + "link_2"] = ("package://%s/meshes/shoulder.stl" % PACKAGE_NAME, None,
                             "stl_solid_header")
        out[p + "link_3"] = ("package://%s/meshes/upper_arm.obj" % PACKAGE_NAME, None, "obj")
        out[p + "link_5"] = ("meshes/forearm.stl", None, "stl")
        out[side + "_hand"] = ("meshes/%s/hand.dae" % side, 0.001, "dae")
    return out


def resolve_mesh_path(filename):
    prefix = "package://%s/" % PACKAGE_NAME
    if filename.startswith(prefix):
        return os.path.join(MODELS_DIR, filename[len(prefix):])
    return os.path.join(MODELS_DIR, filename)


# ----------------------------------------------------------------------------------------
# URDF writing.


def home_comment_lines():
    home = home_configuration()
    lines = ["Home configuration (joint: degrees = radians):"]
    for name in sorted(home, key=joint_sort_key):
        lines.append("  %-22s %7.1f = %s" % (name, home[name] / DEG, fmt(home[name], 6)))
    return lines


def joint_sort_key(name):
    order = ["head_pan_joint", "head_tilt_joint"]
    return (0, order.index(name)) if name in order else (1, name)


def write_urdf(path, links, joints, use_meshes):
    meshes = mesh_assignments() if use_meshes else {}
    out = ['<?xml version="1.0"?>']
    variant = ("mesh variant: same kinematics, inertials and names as dual_arm.urdf; some links"
               " use the mesh files in meshes/" if use_meshes else
               "primitives only (box, cylinder, sphere); visual == collision for every link")
    out.append("<!--")
    out.append("  arttrack dual-arm robot: pedestal, torso, two 7-DoF KUKA-LWR-like arms with"
               " hands, pan-tilt head with a depth camera.")
    out.append("  " + variant + ".")
    out.append("  GENERATED by models/generate_robot.py; edit that script, not this file.")
    out.append("  Frames: base_link at the world origin, x forward, y left, z up;"
               " camera_optical_frame: z forward, x right, y down.")
    out.append("")
    for line in home_comment_lines():
        out.append("  " + line)
    out.append("  In the home pose both hands are in front of the torso just above a 0.75 m table"
               " and the lower arms and hands")
    out.append("  are inside the head camera's 640x480 image (45 deg vertical field of view).")
    out.append("-->")
    out.append('<robot name="arttrack_dual_arm">')
    for name, rgba in MATERIALS:
        out.append('  <material name="%s"><color rgba="%s"/></material>' % (name, fmt_vec(rgba, 3)))
    for link in links:
        out.append('  <link name="%s">' % link.name)
        if link.mass > 0:
            com, inertia = link_inertial(link)
            out.append("    <inertial>")
            out.append('      <origin xyz="%s" rpy="0 0 0"/>' % fmt_vec(com))
            out.append('      <mass value="%s"/>' % fmt_g(link.mass))
            out.append('      <inertia ixx="%s" ixy="%s" ixz="%s" iyy="%s" iyz="%s" izz="%s"/>' %
                       tuple(fmt_g(x) for x in (inertia[0][0], inertia[0][1], inertia[0][2],
                                                inertia[1][1], inertia[1][2], inertia[2][2])))
            out.append("    </inertial>")
        if link.name in meshes:
            filename, scale, _ = meshes[link.name]
            scale_attr = ' scale="%s"' % fmt_vec([scale] * 3) if scale else ""
            geometry = '<mesh filename="%s"%s/>' % (filename, scale_attr)
            elements = [((0, 0, 0), (0, 0, 0), geometry, link.shapes[0].material)]
        else:
            elements = [(s.xyz, s.rpy, s.urdf_geometry(), s.material) for s in link.shapes]
        for xyz, rpy, geometry, material in elements:
            for tag in ("visual", "collision"):
                out.append("    <%s>" % tag)
                out.append('      <origin xyz="%s" rpy="%s"/>' % (fmt_vec(xyz), fmt_vec(rpy)))
                out.append("      <geometry>%s</geometry>" % geometry)
                if tag == "visual":
                    out.append('      <material name="%s"/>' % material)
                out.append("    </%s>" % tag)
        out.append("  </link>")
    for j in joints:
        out += joint_lines(j)
    out.append("</robot>")
    write_text(path, "\n".join(out) + "\n")


def joint_lines(j, extra=()):
    """A <joint> element (movable ones with axis, limit and damping), `extra` lines last."""
    out = ['  <joint name="%s" type="%s">' % (j.name, j.type)]
    out.append('    <parent link="%s"/>' % j.parent)
    out.append('    <child link="%s"/>' % j.child)
    out.append('    <origin xyz="%s" rpy="%s"/>' % (fmt_vec(j.xyz), fmt_vec(j.rpy)))
    if j.type != "fixed":
        out.append('    <axis xyz="%s"/>' % fmt_vec(j.axis))
        out.append('    <limit lower="%s" upper="%s" effort="%s" velocity="%s"/>' %
                   (fmt(j.lower), fmt(j.upper), fmt_g(j.effort), fmt(j.velocity)))
        out.append('    <dynamics damping="%s"/>' % fmt_g(j.damping))
    return out + list(extra) + ["  </joint>"]


def write_text(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        f.write(text)


def write_bytes(path, data):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "wb") as f:
        f.write(data)


# ----------------------------------------------------------------------------------------
# Mesh files. All shells are in the link frame (metres) unless stated.


def link_shells(link):
    return [world_shell(s) for s in link.shapes]


def stl_bytes(shells, header_text):
    """Binary STL, little-endian, one unit normal per triangle (from the winding)."""
    tris = [t for s in shells for t in s.triangles()]
    header = header_text.encode("ascii")
    if len(header) > 80:
        raise ValueError("STL header longer than 80 bytes")
    chunks = [header.ljust(80, b" "), struct.pack("<I", len(tris))]
    for a, b, c in tris:
        n = v_normalized(v_cross(v_sub(b, a), v_sub(c, a)))
        chunks.append(struct.pack("<12fH", *(n + a + b + c), 0))
    return b"".join(chunks)


def obj_text(shells, comments, object_name):
    """Wavefront OBJ with v, vn and f v//vn; quads stay quads, fans stay triangles."""
    lines = ["# " + c for c in comments]
    lines.append("o " + object_name)
    for s in shells:
        lines += ["v %s" % fmt_vec(p, 6) for p in s.positions]
    for s in shells:
        lines += ["vn %s" % fmt_vec(n, 6) for n in s.normals]
    v_off = n_off = 0
    for s in shells:
        for f in s.faces:
            corners = ["%d//%d" % (pi + 1 + v_off, ni + 1 + n_off) for pi, ni in f]
            lines.append("f " + " ".join(corners))
        v_off += len(s.positions)
        n_off += len(s.normals)
    return "\n".join(lines) + "\n"


def hand_dae_nodes(side, hand_link):
    """The hand as two COLLADA nodes: the palm (node translated to the palm centre) and the
    three fingers (node rotated 90 deg about z and translated to the palm top), so a loader
    that ignores node transforms gets a visibly wrong hand."""
    shells = link_shells(hand_link)
    s = 1.0 if side == "left" else -1.0
    palm_pose = Pose(m_identity(), [0.0, 0.0, 0.035])
    fingers_pose = Pose(rot_z(s * 0.5 * math.pi), [0.0, 0.0, 0.070])
    return [("palm", palm_pose, shells[:1], "triangles"),
            ("fingers", fingers_pose, shells[1:], "polylist")]


def dae_text(side, nodes, material_rgba):
    """COLLADA 1.4.1, authored in millimetres. The asset declares COLLADA's defaults (unit
    1 m, Y_UP) on purpose, so assimp applies neither a unit scale nor an axis swap; the
    numbers are millimetres of the hand link frame and the URDF scales them by 0.001."""
    x = ['<?xml version="1.0" encoding="utf-8"?>',
         '<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">',
         "  <asset>",
         "    <contributor><authoring_tool>arttrack models/generate_robot.py</authoring_tool>"
         "<comments>%s hand in millimetres, hand link frame (z = approach); use with URDF"
         " scale 0.001</comments></contributor>" % side,
         "    <created>2000-01-01T00:00:00</created>",
         "    <modified>2000-01-01T00:00:00</modified>",
         '    <unit name="meter" meter="1"/>',
         "    <up_axis>Y_UP</up_axis>",
         "  </asset>",
         "  <library_effects>",
         '    <effect id="hand_effect"><profile_COMMON><technique sid="common"><phong>'
         "<diffuse><color>%s</color></diffuse></phong></technique></profile_COMMON></effect>" %
         fmt_vec(material_rgba, 3),
         "  </library_effects>",
         "  <library_materials>",
         '    <material id="hand_material" name="hand_material">'
         '<instance_effect url="#hand_effect"/></material>',
         "  </library_materials>",
         "  <library_geometries>"]
    for name, pose, shells, primitive in nodes:
        local = [sh.transformed(pose.inverse()) for sh in shells]
        positions, normals, faces = [], [], []
        for sh in local:
            p_off, n_off = len(positions), len(normals)
            positions += [v_scale(p, 1000.0) for p in sh.positions]
            normals += sh.normals
            faces += [[(pi + p_off, ni + n_off) for pi, ni in f] for f in sh.faces]
        if primitive == "triangles":
            faces = [[f[0], f[k], f[k + 1]] for f in faces for k in range(1, len(f) - 1)]
        gid = "%s-mesh" % name
        x.append('    <geometry id="%s" name="%s">' % (gid, name))
        x.append("      <mesh>")
        for src, data in (("positions", positions), ("normals", normals)):
            flat = " ".join(fmt_vec(p, 4 if src == "positions" else 6) for p in data)
            x.append('        <source id="%s-%s">' % (gid, src))
            x.append('          <float_array id="%s-%s-array" count="%d">%s</float_array>' %
                     (gid, src, 3 * len(data), flat))
            x.append('          <technique_common><accessor source="#%s-%s-array" count="%d"'
                     ' stride="3"><param name="X" type="float"/><param name="Y" type="float"/>'
                     '<param name="Z" type="float"/></accessor></technique_common>' %
                     (gid, src, len(data)))
            x.append("        </source>")
        x.append('        <vertices id="%s-vertices"><input semantic="POSITION" source="#%s-'
                 'positions"/></vertices>' % (gid, gid))
        inputs = ('<input semantic="VERTEX" source="#%s-vertices" offset="0"/><input semantic='
                  '"NORMAL" source="#%s-normals" offset="1"/>' % (gid, gid))
        indices = " ".join("%d %d" % c for f in faces for c in f)
        if primitive == "triangles":
            x.append('        <triangles material="hand_material" count="%d">%s<p>%s</p>'
                     "</triangles>" % (len(faces), inputs, indices))
        else:
            vcount = " ".join(str(len(f)) for f in faces)
            x.append('        <polylist material="hand_material" count="%d">%s<vcount>%s'
                     "</vcount><p>%s</p></polylist>" % (len(faces), inputs, vcount, indices))
        x.append("      </mesh>")
        x.append("    </geometry>")
    x.append("  </library_geometries>")
    x.append("  <library_visual_scenes>")
    x.append('    <visual_scene id="hand_scene" name="hand_scene">')
    for name, pose, _, _ in nodes:
        rows = []
        for i in range(3):
            rows += [pose.R[i][0], pose.R[i][1], pose.R[i][2], pose.t[i] * 1000.0]
        rows += [0.0, 0.0, 0.0, 1.0]
        x.append('      <node id="%s" name="%s" type="NODE">' % (name, name))
        x.append('        <matrix sid="transform">%s</matrix>' % fmt_vec(rows, 6))
        x.append('        <instance_geometry url="#%s-mesh"><bind_material><technique_common>'
                 '<instance_material symbol="hand_material" target="#hand_material"/>'
                 "</technique_common></bind_material></instance_geometry>" % name)
        x.append("      </node>")
    x.append("    </visual_scene>")
    x.append("  </library_visual_scenes>")
    x.append('  <scene><instance_visual_scene url="#hand_scene"/></scene>')
    x.append("</COLLADA>")
    return "\n".join(x) + "\n"


def write_meshes(links):
    """Writes every mesh file of the mesh variant; returns {path: (kind, link)}."""
    by_name = {l.name: l for l in links}
    written = {}
    rgba = dict(MATERIALS)
    for link_name, (filename, _, kind) in mesh_assignments().items():
        path = resolve_mesh_path(filename)
        if path in written:
            continue  # both arms share the file
        link = by_name[link_name]
        shells = link_shells(link)
        base = os.path.splitext(os.path.basename(path))[0]
        if kind == "stl":
            data = stl_bytes(shells, "arttrack %s: binary STL, little-endian, metres, link frame"
                             % base)
            write_bytes(path, data)
        elif kind == "stl_solid_header":
            # The header starts with "solid" like an ASCII STL: a known pitfall for loaders
            # that sniff the first bytes instead of checking 84 + 50 * count == file size.
            data = stl_bytes(shells, "solid %s: BINARY STL despite this header, metres, link frame"
                             % base)
            write_bytes(path, data)
        elif kind == "obj":
            text = obj_text(shells, ["arttrack %s: metres, link frame (z along the arm)" % base,
                                     "GENERATED by models/generate_robot.py"], base)
            write_text(path, text)
        elif kind == "dae":
            side = link_name.split("_")[0]
            write_text(path, dae_text(side, hand_dae_nodes(side, link), rgba["hand_black"]))
        written[path] = (kind, link)
    return written


# ----------------------------------------------------------------------------------------
# Reading the written files back (independent of the writers above).


def read_stl(path):
    with open(path, "rb") as f:
        data = f.read()
    header = data[:80]
    (count,) = struct.unpack_from("<I", data, 80)
    if len(data) != 84 + 50 * count:
        raise ValueError("%s: size %d != 84 + 50 * %d" % (path, len(data), count))
    tris, normals = [], []
    for k in range(count):
        v = struct.unpack_from("<12f", data, 84 + 50 * k)
        normals.append(list(v[0:3]))
        tris.append((list(v[3:6]), list(v[6:9]), list(v[9:12])))
    return header, tris, normals


def read_obj(path):
    positions, normals, tris, polygon_sizes = [], [], [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts or parts[0].startswith("#"):
                continue
            if parts[0] == "v":
                positions.append([float(x) for x in parts[1:4]])
            elif parts[0] == "vn":
                normals.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                corners = []
                for c in parts[1:]:
                    vi, empty, ni = c.split("/")
                    if empty != "":
                        raise ValueError("%s: expected v//vn, got %s" % (path, c))
                    corners.append((positions[int(vi) - 1], normals[int(ni) - 1]))
                polygon_sizes.append(len(corners))
                for k in range(1, len(corners) - 1):
                    tris.append((corners[0][0], corners[k][0], corners[k + 1][0]))
    return tris, polygon_sizes


def read_dae(path):
    """Triangles per node, in the file's units, after applying each node's <matrix>."""
    ns = {"c": "http://www.collada.org/2005/11/COLLADASchema"}
    root = ET.parse(path).getroot()
    geometries = {g.get("id"): g for g in root.iter("{%s}geometry" % ns["c"])}
    result = []
    for node in root.iter("{%s}node" % ns["c"]):
        m = [float(x) for x in node.find("c:matrix", ns).text.split()]
        pose = Pose([m[0:3], m[4:7], m[8:11]], [m[3], m[7], m[11]])
        gid = node.find("c:instance_geometry", ns).get("url")[1:]
        mesh = geometries[gid].find("c:mesh", ns)
        arrays = {}
        for src in mesh.findall("c:source", ns):
            vals = [float(x) for x in src.find("c:float_array", ns).text.split()]
            arrays["#" + src.get("id")] = [vals[i:i + 3] for i in range(0, len(vals), 3)]
        vert_src = mesh.find("c:vertices/c:input", ns).get("source")
        positions = arrays[vert_src]
        tris = []
        for prim in list(mesh.findall("c:triangles", ns)) + list(mesh.findall("c:polylist", ns)):
            stride = len(prim.findall("c:input", ns))
            idx = [int(x) for x in prim.find("c:p", ns).text.split()]
            pos_idx = idx[0::stride]
            if prim.tag.endswith("triangles"):
                sizes = [3] * (len(pos_idx) // 3)
            else:
                sizes = [int(x) for x in prim.find("c:vcount", ns).text.split()]
            k = 0
            for n in sizes:
                poly = [pose.apply(positions[i]) for i in pos_idx[k:k + n]]
                k += n
                for j in range(1, n - 1):
                    tris.append((poly[0], poly[j], poly[j + 1]))
        result.append((node.get("name"), tris))
    return result


def soup_checks(tris, quantum=1e-6):
    """Closed and consistently wound: every directed edge exactly once, its reverse exactly
    once. Returns (signed volume, bounding box)."""
    def key(p):
        return tuple(int(round(x / quantum)) for x in p)
    edges = {}
    for a, b, c in tris:
        ka, kb, kc = key(a), key(b), key(c)
        for e in ((ka, kb), (kb, kc), (kc, ka)):
            edges[e] = edges.get(e, 0) + 1
    for (u, w), n in edges.items():
        if n != 1 or edges.get((w, u), 0) != 1:
            raise ValueError("open or inconsistently wound edge %s -> %s" % (u, w))
    volume = sum(v_dot(a, v_cross(b, c)) for a, b, c in tris) / 6.0
    pts = [p for t in tris for p in t]
    lo = [min(p[i] for p in pts) for i in range(3)]
    hi = [max(p[i] for p in pts) for i in range(3)]
    return volume, (lo, hi)


def shapes_bbox(shapes):
    """Exact bounding box of axis-aligned primitives in the link frame."""
    lo, hi = [1e9] * 3, [-1e9] * 3
    for s in shapes:
        if any(abs(a) > 1e-12 for a in s.rpy):
            raise ValueError("shapes_bbox expects axis-aligned shapes")
        if s.kind == "box":
            h = [0.5 * x for x in s.size]
        elif s.kind == "cylinder":
            h = [s.radius, s.radius, 0.5 * s.length]
        else:
            h = [s.radius] * 3
        lo = [min(lo[i], s.xyz[i] - h[i]) for i in range(3)]
        hi = [max(hi[i], s.xyz[i] + h[i]) for i in range(3)]
    return lo, hi


def check_shell_outward(shell):
    """Each shell is convex, so every face normal (from the winding) must point away from
    the shell's centroid, and the stored normals must agree with it."""
    centre = v_scale([sum(p[i] for p in shell.positions) for i in range(3)],
                     1.0 / len(shell.positions))
    for f in shell.faces:
        pts = [shell.positions[pi] for pi, _ in f]
        n = v_cross(v_sub(pts[1], pts[0]), v_sub(pts[2], pts[0]))
        mid = v_scale([sum(p[i] for p in pts) for i in range(3)], 1.0 / len(pts))
        if v_dot(n, v_sub(mid, centre)) <= 0.0:
            raise ValueError("inward face")
        for _, ni in f:
            if v_dot(shell.normals[ni], n) <= 0.0:
                raise ValueError("vertex normal disagrees with the winding")


# ----------------------------------------------------------------------------------------
# README (generated with the tables, so it cannot drift from the model).


def shape_summary(shape):
    at = "at (%s)" % fmt_vec(shape.xyz, 4)
    if shape.kind == "box":
        return "box %s %s" % ("x".join(fmt(v, 4) for v in shape.size), at)
    if shape.kind == "cylinder":
        return "cylinder r %s l %s %s" % (fmt(shape.radius, 4), fmt(shape.length, 4), at)
    return "sphere r %s %s" % (fmt(shape.radius, 4), at)


MESH_PURPOSE = {
    "stl": "binary STL, little-endian, unit normals, relative path (resolved against the"
           " URDF's folder)",
    "stl_solid_header": "binary STL whose 80-byte header starts with `solid` (loaders that"
                        " sniff the first bytes take it for ASCII); `package://` path",
    "obj": "Wavefront OBJ: `v`, `vn`, `f v//vn`, triangles (cylinder caps) and quads (sides);"
           " `package://` path",
    "dae": "COLLADA, two sub-meshes (palm: `<triangles>`, fingers: `<polylist>` of quads) under"
           " two `<node>`s with a `<matrix>` each (the fingers' node rotates 90 deg about z), in"
           " millimetres with URDF `scale=\"0.001 0.001 0.001\"`; left/right files share the base"
           " name `hand` in different folders and are mirror images",
}


def readme_text(links, joints, report):
    home = home_configuration()
    meshes = mesh_assignments()
    out = []
    w = out.append
    w("# arttrack robot model")
    w("")
    w("GENERATED by `models/generate_robot.py` (python3, standard library only, deterministic)"
      " together with the URDFs and meshes. Do not edit them by hand: change the script and run")
    w("")
    w("    python3 models/generate_robot.py")
    w("")
    w("It rewrites `dual_arm.urdf`, `dual_arm_meshes.urdf`, `meshes/` and this README, reads the"
      " files back and checks them; it exits with status 1 and names the failed check otherwise."
      " Two runs give byte-identical files.")
    w("")
    w("| file | content |")
    w("|---|---|")
    w("| `dual_arm.urdf` | the robot, primitives only (`box`, `cylinder`, `sphere`; no capsule,"
      " which MuJoCo 2.2's URDF import lacks). The single source of truth for the simulator"
      " (MuJoCo 2.2) and the tracker (urdfdom). |")
    w("| `dual_arm_meshes.urdf` | the same links, joints, names, origins and inertials; a few links"
      " use the mesh files below instead of primitives. For testing the tracker's mesh loading"
      " (urdfdom + assimp); MuJoCo 2.2 cannot load it (no COLLADA). |")
    w("| `meshes/` | STL, OBJ and COLLADA files tessellated from the same primitives. |")
    w("| `dual_arm_sculpted.urdf`, `arm7_sculpted.urdf`, `scene_sculpted.yaml`,"
      " `arm7_sculpted_scene.yaml`, `meshes/sculpted/` | GENERATED by `generate_sculpted.py`:"
      " both robots with every primitive a sculpted, finely tessellated mesh (330 000 and"
      " 162 000 triangles, about 130 000 per arm, as makers publish theirs), and their scenes."
      " For benchmarks and tests of the tracker on published-style meshes"
      " (`scenarios/sculpted/`, docs/performance.md \"Meshes\"). |")
    w("")
    w("## The robot")
    w("")
    w("A fixed pedestal (`base_link`, floor plate and column up to 0.80 m) carries the `torso`"
      " (box 0.30 x 0.36 x 0.50 m, top at 1.30 m). Two 7-DoF arms with KUKA LWR 4 proportions"
      " are mounted on the torso's sides, each ending in a hand with a palm, two fingers and a"
      " thumb (no rotation about the approach axis maps it onto itself, so its orientation is"
      " visible in a depth image). A pan-tilt head on a neck post at the back of the torso top"
      " carries the depth camera at about 1.64 m.")
    w("")
    w("## Frames")
    w("")
    w("- `base_link`: the world origin on the floor; x forward, y left, z up.")
    w("- `S_arm_link_0` (S = `left`, `right`): the arm's base, mounted 2 cm outside the torso's"
      " side face at 1.10 m; its z (the axis of joint 1) points out, forward and up,"
      " (0.587, +-0.492, 0.643) in the world. The right arm is the mirror image of the left.")
    w("- `S_arm_link_i` (i = 1..7): origin on joint i; joint i+1 lies on the link's +z (LWR"
      " convention). Joints 1, 3, 5, 7 turn about the link's z (along the arm), joints 2, 4, 6"
      " about its y (they bend the arm). Mount -> shoulder (joint 2) 0.31 m, shoulder -> elbow"
      " (joint 4) 0.40 m, elbow -> wrist (joint 6) 0.39 m, wrist -> flange (joint 7) 0.078 m.")
    w("- `S_hand`: on the flange (`S_arm_link_7`'s origin), same axes; z is the approach"
      " direction. The two fingers are on the hand's +y side for the left hand and -y for the"
      " right hand, the thumb opposite.")
    w("- `S_ee`: the grasp point between fingers and thumb, %s m along the hand's z, same"
      " axes as the hand. No geometry." % fmt(HAND_EE_Z))
    w("- `camera_link`: ROS body convention (x forward, y left, z up), 0.06 m in front of the"
      " tilt axis, in front of all head geometry (the camera never sees the inside of the head).")
    w("- `camera_optical_frame`: rpy (-pi/2, 0, -pi/2) from `camera_link`: z forward (optical"
      " axis), x right, y down. No geometry.")
    w("- `head_tilt_joint` > 0 looks down; `head_pan_joint` > 0 looks left.")
    w("")
    w("The checks assume a %dx%d camera with a %g deg vertical field of view (fx = fy = %.2f px,"
      " cx = %g, cy = %g)." % (CAMERA_WIDTH, CAMERA_HEIGHT, CAMERA_FOVY_DEG,
                               0.5 * CAMERA_HEIGHT / math.tan(0.5 * CAMERA_FOVY_DEG * DEG),
                               0.5 * CAMERA_WIDTH, 0.5 * CAMERA_HEIGHT))
    w("")
    w("## Links")
    w("")
    w("Inertials: the mass spread over the link's primitives in proportion to their volume;"
      " `<inertial>` origin at the centre of mass, full tensor in the link's axes. Every link"
      " with geometry has identical `<visual>` and `<collision>` elements (materials only on"
      " visuals).")
    w("")
    w("| link | parent joint | mass (kg) | geometry (link frame, m) |")
    w("|---|---|---|---|")
    parent_joint = {j.child: j.name for j in joints}
    for l in links:
        geo = "; ".join(shape_summary(s) for s in l.shapes) or "none (frame only)"
        mesh = meshes.get(l.name)
        if mesh:
            geo += "; mesh variant: `%s`" % mesh[0]
        w("| `%s` | %s | %s | %s |" % (l.name, "`%s`" % parent_joint[l.name]
                                      if l.name in parent_joint else "(root)",
                                      fmt_g(l.mass) if l.mass else "-", geo))
    w("")
    w("## Joints")
    w("")
    w("Origins are the child frame in the parent frame (URDF). Limits in degrees here, radians in"
      " the URDF. Arm joints have `damping` %s N m s/rad, head joints 0.1." % fmt_g(LWR_DAMPING))
    w("")
    w("| joint | type | parent -> child | origin xyz (m) | origin rpy (rad) | axis |"
      " limits (deg) | effort (N m) | velocity (rad/s) |")
    w("|---|---|---|---|---|---|---|---|---|")
    for j in joints:
        if j.type == "revolute":
            lim = "%.0f .. %.0f" % (j.lower / DEG, j.upper / DEG)
            rest = "`%s` | %s | %s | %s" % (fmt_vec(j.axis), lim, fmt_g(j.effort),
                                             fmt(j.velocity, 3))
        else:
            rest = "- | - | - | -"
        w("| `%s` | %s | `%s` -> `%s` | %s | %s | %s |" % (
            j.name, j.type, j.parent, j.child, fmt_vec(j.xyz, 4), fmt_vec(j.rpy, 6), rest))
    w("")
    w("## Home configuration")
    w("")
    w("Both hands in front of the torso just above a %.2f m table, the head looking down %g deg;"
      " the lower arms (links 4-7) and hands lie inside the camera image with little hidden"
      " behind other links, and no two links touch. The right arm mirrors the left (joints 1, 3,"
      " 5, 7 change sign). Also in a comment at the top of both URDFs." %
      (TABLE_TOP_Z, HOME_HEAD_DEG["head_tilt_joint"]))
    w("")
    w("| joint | degrees | radians |")
    w("|---|---|---|")
    for name in sorted(home, key=joint_sort_key):
        w("| `%s` | %.1f | %s |" % (name, home[name] / DEG, fmt(home[name], 6)))
    w("")
    w("The generator's home-pose checks, as printed when these files were generated:")
    w("")
    w("```")
    start = next(i for i, line in enumerate(report) if line.startswith("camera_optical_frame"))
    out += report[start:]
    w("```")
    w("")
    w("## Mesh variant (`dual_arm_meshes.urdf`)")
    w("")
    w("Each mesh file is one link's primitives tessellated (cylinders 32 segments, spheres 32 x"
      " 16, vertices on the true surface, so the volume is 99-100%% of the primitives'), in the"
      " link frame: closed, outward, wound counter-clockwise seen from outside. Visual and"
      " collision use the same file. `package://%s/` is this `models/` folder; relative paths"
      " are relative to the URDF's folder." % PACKAGE_NAME)
    w("")
    w("| links | URDF filename | exercises |")
    w("|---|---|---|")
    seen = {}
    for link_name, (filename, _, kind) in meshes.items():
        seen.setdefault((filename, kind), []).append(link_name)
    for (filename, kind), names in seen.items():
        w("| %s | `%s` | %s |" % (", ".join("`%s`" % n for n in names), filename,
                                  MESH_PURPOSE[kind]))
    w("")
    w("Loader notes:")
    w("")
    w("- The COLLADA files declare COLLADA's defaults, `<unit meter=\"1\"/>` and"
      " `<up_axis>Y_UP</up_axis>`, so assimp applies neither a unit scale nor an axis"
      " conversion: the numbers are millimetres in the hand link frame (z = approach), and the"
      " URDF's scale turns them into metres. A loader must apply the node matrices (assimp"
      " keeps them in the node tree) and then the URDF scale.")
    w("- OBJ and COLLADA contain quads: triangulate (assimp: `aiProcess_Triangulate`).")
    w("- MuJoCo 2.2 reads binary STL (also with the `solid` header) and OBJ, not COLLADA, so it"
      " cannot load `dual_arm_meshes.urdf`; its URDF import also strips mesh paths to base"
      " names, so `left/hand.dae` and `right/hand.dae` would collide (both are named `hand`).")
    w("")
    w("## Using the model in MuJoCo 2.2")
    w("")
    w("Insert `<mujoco><compiler discardvisual=\"false\" fusestatic=\"false\"/></mujoco>` inside"
      " `<robot>` (without it fixed links such as `camera_optical_frame` and the `_ee` frames are"
      " merged away and visual geoms dropped). Every URDF link then becomes a body of the same"
      " name. URDF has no cameras or actuators: add them in MJCF.")
    w("")
    w("## What the generator checks")
    w("")
    w("- URDF structure: exactly the expected link and joint names, one root, visual =="
      " collision everywhere, only primitives in `dual_arm.urdf`, and identical joints and"
      " inertials in both URDFs.")
    w("- Mesh files, read back by independent parsers: closed and consistently wound (every"
      " directed edge once, its reverse once), each shell outward, STL normals agree with the"
      " winding, volume and bounding box match the primitives.")
    w("- Home pose, by forward kinematics of the written `dual_arm.urdf`: joints at least 0.2"
      " rad inside their limits; elbows, wrists, hands and grasp points, and every surface"
      " sample of links 4-7 and the hands, project into the image; little of them is hidden"
      " behind other links (ray casting against the exact primitives); no robot geometry"
      " within 0.15 m of the lens in view and the head entirely behind the camera origin; grasp"
      " points 0.5-0.8 m in front at table height, every arm point 2 cm above the table; no two"
      " links that a simulator would collide (not parent and child, not both fixed to the"
      " world) come within 5 mm of each other.")
    return "\n".join(out) + "\n"


# ----------------------------------------------------------------------------------------
# Checks on the written URDF files.


class Failure(Exception):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def parse_floats(text, default):
    return [float(x) for x in text.split()] if text is not None else list(default)


def parse_origin(elem):
    o = elem.find("origin") if elem is not None else None
    if o is None:
        return [0.0] * 3, [0.0] * 3
    return parse_floats(o.get("xyz"), [0, 0, 0]), parse_floats(o.get("rpy"), [0, 0, 0])


class ParsedUrdf:
    """The parts of a URDF file the checks need, read with ElementTree."""

    def __init__(self, path):
        root = ET.parse(path).getroot()
        self.links, self.joints = {}, {}
        self.link_order, self.joint_order = [], []
        for l in root.findall("link"):
            name = l.get("name")
            entry = {"visual": [], "collision": [], "inertial": None}
            for tag in ("visual", "collision"):
                for e in l.findall(tag):
                    g = e.find("geometry")[0]
                    xyz, rpy = parse_origin(e)
                    entry[tag].append((xyz, rpy, g.tag, dict(g.attrib)))
            inertial = l.find("inertial")
            if inertial is not None:
                xyz, rpy = parse_origin(inertial)
                entry["inertial"] = (xyz, rpy, float(inertial.find("mass").get("value")),
                                     dict(inertial.find("inertia").attrib))
            self.links[name] = entry
            self.link_order.append(name)
        for j in root.findall("joint"):
            xyz, rpy = parse_origin(j)
            axis = j.find("axis")
            limit = j.find("limit")
            self.joints[j.get("name")] = {
                "type": j.get("type"), "parent": j.find("parent").get("link"),
                "child": j.find("child").get("link"), "xyz": xyz, "rpy": rpy,
                "axis": parse_floats(axis.get("xyz") if axis is not None else None, [1, 0, 0]),
                "limit": dict(limit.attrib) if limit is not None else None}
            self.joint_order.append(j.get("name"))
        children = {j["child"] for j in self.joints.values()}
        roots = [n for n in self.link_order if n not in children]
        check(len(roots) == 1, "%s: expected one root link, got %s" % (path, roots))
        self.root = roots[0]

    def forward_kinematics(self, q):
        """World pose (T_world_link) of every link for joint angles q (radians, default 0)."""
        poses = {self.root: Pose()}
        pending = list(self.joint_order)
        while pending:
            progressed = False
            for name in list(pending):
                j = self.joints[name]
                if j["parent"] not in poses:
                    continue
                t = poses[j["parent"]] * Pose.from_xyz_rpy(j["xyz"], j["rpy"])
                if j["type"] == "revolute":
                    t = t * Pose(axis_angle_matrix(j["axis"], q.get(name, 0.0)))
                poses[j["child"]] = t
                pending.remove(name)
                progressed = True
            check(progressed, "joint tree is disconnected")
        return poses

    def shapes(self, link_name):
        out = []
        for xyz, rpy, tag, a in self.links[link_name]["collision"]:
            if tag == "box":
                out.append(Box(parse_floats(a["size"], None), xyz, rpy))
            elif tag == "cylinder":
                out.append(Cylinder(float(a["radius"]), float(a["length"]), xyz, rpy))
            elif tag == "sphere":
                out.append(Sphere(float(a["radius"]), xyz))
        return out


def expected_names():
    links = ["base_link", "torso", "neck_link", "head_pan_link", "head_tilt_link", "camera_link",
             "camera_optical_frame"]
    joints = ["torso_joint", "neck_joint", "head_pan_joint", "head_tilt_joint", "camera_joint",
              "camera_optical_joint"]
    for s in SIDES:
        links += ["%s_arm_link_%d" % (s, i) for i in range(8)] + [s + "_hand", s + "_ee"]
        joints += ["%s_arm_mount_joint" % s] + ["%s_arm_joint_%d" % (s, i) for i in range(1, 8)]
        joints += [s + "_hand_joint", s + "_ee_joint"]
    return links, joints


def check_urdf_structure(urdf, mesh_variant):
    links, joints = expected_names()
    check(sorted(urdf.links) == sorted(links), "unexpected link set")
    check(sorted(urdf.joints) == sorted(joints), "unexpected joint set")
    for name, entry in urdf.links.items():
        check(entry["visual"] == entry["collision"], "%s: visual != collision" % name)
        for xyz, rpy, tag, a in entry["collision"]:
            allowed = ("box", "cylinder", "sphere") + (("mesh",) if mesh_variant else ())
            check(tag in allowed, "%s: geometry %s not allowed" % (name, tag))
        if entry["collision"]:
            inertial = entry["inertial"]
            check(inertial is not None and inertial[2] > 0, "%s: no mass" % name)
    for name in ("camera_optical_frame", "left_ee", "right_ee"):
        check(not urdf.links[name]["visual"], name + " must carry no geometry")


def check_same_kinematics(a, b):
    check(a.joint_order == b.joint_order and a.joints == b.joints, "joints differ")
    for name in a.links:
        check(a.links[name]["inertial"] == b.links[name]["inertial"], name + ": inertial differs")


def project(camera, p_optical):
    fx, fy, cx, cy = camera
    x, y, z = p_optical
    return fx * x / z + cx, fy * y / z + cy


def link_world_points(urdf, poses, link_name):
    pts = []
    for s in urdf.shapes(link_name):
        t = poses[link_name] * s.pose()
        pts += [t.apply(p) for p in s.local_surface_points()]
    return pts


def occluded_fraction(urdf, poses, eye, link_name):
    """Fraction of a link's outer surface samples whose line of sight from `eye` passes
    through another link (the link hiding its own back side does not count)."""
    others = []
    for n in urdf.link_order:
        if n == link_name:
            continue
        for s in urdf.shapes(n):
            inv = (poses[n] * s.pose()).inverse()
            others.append((inv, inv.apply(eye), s))
    # Samples inside or on another link (e.g. a cap pressed against the next link) are not
    # on the robot's outer surface and are skipped.
    pts = [p for p in link_world_points(urdf, poses, link_name)
           if min(s.local_sdf(inv.apply(p)) for inv, _, s in others) > 0.002]
    blocked = 0
    for p in pts:
        d = v_sub(p, eye)
        d = v_scale(d, 1.0 - 0.002 / v_norm(d))  # stop 2 mm short of the surface
        for inv, o, s in others:
            if s.local_segment_hits(o, inv.rotate(d)):
                blocked += 1
                break
    return blocked / float(len(pts))


def static_links(urdf):
    """Links welded to the root through fixed joints only (MuJoCo never collides two of them)."""
    static = {urdf.root}
    changed = True
    while changed:
        changed = False
        for j in urdf.joints.values():
            if j["type"] == "fixed" and j["parent"] in static and j["child"] not in static:
                static.add(j["child"])
                changed = True
    return static


def min_clearance(urdf, poses):
    """Smallest signed distance between the surfaces of any two links that a simulator would
    collide (not parent and child, not both welded to the world), found by sampling each
    link's surfaces against the other link's exact primitives. Returns sorted (d, a, b)."""
    parent_of = {j["child"]: j["parent"] for j in urdf.joints.values()}
    static = static_links(urdf)
    geo = [n for n in urdf.link_order if urdf.shapes(n)]
    points = {n: link_world_points(urdf, poses, n) for n in geo}
    inv_shapes = {n: [((poses[n] * s.pose()).inverse(), s) for s in urdf.shapes(n)] for n in geo}
    spheres = {}
    for n in geo:
        c = v_scale([sum(p[i] for p in points[n]) for i in range(3)], 1.0 / len(points[n]))
        spheres[n] = (c, max(v_norm(v_sub(p, c)) for p in points[n]))
    results = []
    for ia, a in enumerate(geo):
        for b in geo[ia + 1:]:
            if parent_of.get(a) == b or parent_of.get(b) == a or (a in static and b in static):
                continue
            (ca, ra), (cb, rb) = spheres[a], spheres[b]
            gap = v_norm(v_sub(ca, cb)) - ra - rb
            if gap > 0.05:
                results.append((gap, a, b))
                continue
            d = 1e9
            for src, dst in ((a, b), (b, a)):
                for p in points[src]:
                    for inv, s in inv_shapes[dst]:
                        d = min(d, s.local_sdf(inv.apply(p)))
            results.append((d, a, b))
    return sorted(results)


def check_home_pose(urdf, report):
    home = home_configuration()
    for name, q in home.items():
        lim = urdf.joints[name]["limit"]
        check(float(lim["lower"]) + 0.2 <= q <= float(lim["upper"]) - 0.2,
              "%s: home %.3f rad within 0.2 rad of a limit" % (name, q))
    tilt_deg = home["head_tilt_joint"] / DEG
    check(35.0 <= tilt_deg <= 45.0, "head tilt %.1f deg outside 35-45" % tilt_deg)
    poses = urdf.forward_kinematics(home)
    T_world_opt = poses["camera_optical_frame"]
    T_opt_world = T_world_opt.inverse()
    fy = 0.5 * CAMERA_HEIGHT / math.tan(0.5 * CAMERA_FOVY_DEG * DEG)
    camera = (fy, fy, 0.5 * CAMERA_WIDTH, 0.5 * CAMERA_HEIGHT)
    optical_axis = T_world_opt.rotate([0, 0, 1])
    down_deg = math.degrees(math.asin(-optical_axis[2]))
    report.append("camera_optical_frame at home: position %s m, optical axis %s (%.1f deg below"
                  " horizontal)" % (fmt_vec(T_world_opt.t, 3), fmt_vec(optical_axis, 3), down_deg))
    check(abs(down_deg - tilt_deg) < 1e-6, "optical axis does not follow the tilt")
    right = T_world_opt.rotate([1, 0, 0])
    check(right[1] < -0.99, "optical x is not to the robot's right")

    report.append("Projected home positions (640x480, fovy 45 deg, pixel centres at u+0.5):")
    report.append("  %-18s %-24s %8s %8s %8s" % ("frame", "world xyz (m)", "u", "v", "depth"))
    for side in SIDES:
        for label, link in (("elbow", "%s_arm_link_4" % side), ("wrist", "%s_arm_link_6" % side),
                            ("hand", side + "_hand"), ("ee", side + "_ee")):
            p = poses[link].t
            po = T_opt_world.apply(p)
            u, v = project(camera, po)
            report.append("  %-18s %-24s %8.1f %8.1f %8.3f" %
                          (side + " " + label, fmt_vec(p, 3), u, v, po[2]))
            check(po[2] > 0 and 0 <= u < CAMERA_WIDTH and 0 <= v < CAMERA_HEIGHT,
                  "%s %s outside the image" % (side, label))
    # The whole lower arm (links 4-7, elbow housing included) and the hand, sampled on their
    # surfaces, must project inside the image.
    for side in SIDES:
        names = ["%s_arm_link_%d" % (side, i) for i in (4, 5, 6, 7)] + [side + "_hand"]
        us, vs = [], []
        for n in names:
            for p in link_world_points(urdf, poses, n):
                po = T_opt_world.apply(p)
                check(po[2] > 0.1, "%s: point behind or too near the camera" % n)
                u, v = project(camera, po)
                us.append(u)
                vs.append(v)
        report.append("  %s lower arm + hand surface spans u %.0f..%.0f, v %.0f..%.0f" %
                      (side, min(us), max(us), min(vs), max(vs)))
        check(min(us) >= 0 and max(us) < CAMERA_WIDTH and min(vs) >= 0 and max(vs) < CAMERA_HEIGHT,
              "%s lower arm or hand leaves the image" % side)
    # Line of sight: the torso, the other arm or the arm's own links must not hide much of
    # the lower arm and hand.
    max_occluded = {4: 0.5, 5: 0.2, 6: 0.5, 7: 0.6, "hand": 0.1}
    for side in SIDES:
        parts = []
        for key in (4, 5, 6, 7, "hand"):
            n = side + "_hand" if key == "hand" else "%s_arm_link_%d" % (side, key)
            f = occluded_fraction(urdf, poses, T_world_opt.t, n)
            parts.append("%s %.0f%%" % (n.replace(side + "_", ""), 100.0 * f))
            check(f <= max_occluded[key], "%s: %.0f%% of its surface hidden behind other links"
                  % (n, 100.0 * f))
        report.append("  %s surface samples hidden behind other links: %s" %
                      (side, ", ".join(parts)))
    # Nothing of the robot between the lens and 0.15 m in front of it; the head is behind.
    for n in urdf.link_order:
        for p in link_world_points(urdf, poses, n):
            po = T_opt_world.apply(p)
            if n == "head_tilt_link":
                check(po[2] < -0.005, "head geometry in front of the camera origin")
            elif 0 < po[2] < 0.15:
                u, v = project(camera, po)
                check(not (0 <= u < CAMERA_WIDTH and 0 <= v < CAMERA_HEIGHT),
                      "%s within 0.15 m of the camera and in view" % n)
    # Hands in front of the torso at table height.
    for side in SIDES:
        ee = poses[side + "_ee"].t
        check(0.5 <= ee[0] <= 0.8, "%s_ee x = %.3f not 0.5-0.8 m in front" % (side, ee[0]))
        check(TABLE_TOP_Z < ee[2] < TABLE_TOP_Z + 0.2, "%s_ee not at table height" % side)
        lowest = min(p[2] for n in ["%s_arm_link_%d" % (side, i) for i in range(8)] +
                     [side + "_hand"] for p in link_world_points(urdf, poses, n))
        report.append("  %s arm and hand lowest point z = %.3f m (table top %.2f m)" %
                      (side, lowest, TABLE_TOP_Z))
        check(lowest > TABLE_TOP_Z + 0.02, "%s arm reaches into the table" % side)
    # No two links intersect (arms vs torso, head, pedestal, each other).
    clearances = min_clearance(urdf, poses)
    margin = 0.005
    worst = clearances[0]
    report.append("Home-pose clearance (sampled surfaces vs exact primitives), closest pairs:")
    for d, a, b in clearances[:5]:
        report.append("  %-16s %-16s %6.3f m" % (a, b, d))
    torso_pairs = [c for c in clearances if "torso" in (c[1], c[2]) and "arm" in c[1] + c[2]]
    report.append("  closest arm link to the torso: %s at %.3f m" %
                  (torso_pairs[0][1] if torso_pairs[0][2] == "torso" else torso_pairs[0][2],
                   torso_pairs[0][0]))
    check(worst[0] > margin, "%s and %s intersect or touch at home (%.4f m)" % (worst[1], worst[2],
                                                                                worst[0]))
    return poses


def check_mesh_files(written, report):
    report.append("Mesh files (read back; closed, consistently wound, outward, extent of the"
                  " primitives):")
    for path in sorted(written):
        kind, link = written[path]
        rel = os.path.relpath(path, MODELS_DIR)
        expected_volume = sum(s.volume() for s in link.shapes)
        for sh in link_shells(link):
            check_shell_outward(sh)
        bbox_expected = shapes_bbox(link.shapes)
        if kind.startswith("stl"):
            header, tris, normals = read_stl(path)
            starts_solid = header.startswith(b"solid")
            check(starts_solid == (kind == "stl_solid_header"), rel + ": header")
            for (a, b, c), n in zip(tris, normals):
                w = v_cross(v_sub(b, a), v_sub(c, a))
                check(v_dot(w, n) > 0 and abs(v_norm(n) - 1) < 1e-5, rel + ": bad normal")
            detail = "binary STL, %d triangles, header starts with 'solid': %s" % (
                len(tris), "yes" if starts_solid else "no")
        elif kind == "obj":
            tris, sizes = read_obj(path)
            check(3 in sizes and 4 in sizes, rel + ": needs triangles and quads")
            detail = "OBJ, %d triangles + %d quads, v//vn" % (sizes.count(3), sizes.count(4))
        else:
            nodes = read_dae(path)
            check(len(nodes) == 2, rel + ": expected two nodes")
            tris = [tuple(v_scale(p, 0.001) for p in t) for _, ts in nodes for t in ts]
            detail = "COLLADA, nodes %s, %d triangles, millimetres" % (
                "+".join(n for n, _ in nodes), len(tris))
        volume, (lo, hi) = soup_checks(tris)
        check(abs(volume - expected_volume) < 0.03 * expected_volume,
              "%s: volume %.6g vs primitives %.6g" % (rel, volume, expected_volume))
        err = max(max(abs(lo[i] - bbox_expected[0][i]), abs(hi[i] - bbox_expected[1][i]))
                  for i in range(3))
        check(err < 2e-6, "%s: extent differs from the primitives by %.3g m" % (rel, err))
        report.append("  %-24s %s; volume %.1f%% of the primitives'" %
                      (rel, detail, 100.0 * volume / expected_volume))


def main():
    links, joints = build_robot()
    primitive_path = os.path.join(MODELS_DIR, "dual_arm.urdf")
    mesh_path = os.path.join(MODELS_DIR, "dual_arm_meshes.urdf")
    write_urdf(primitive_path, links, joints, use_meshes=False)
    write_urdf(mesh_path, links, joints, use_meshes=True)
    written = write_meshes(links)

    report = ["Wrote %s, %s and %d mesh files." % (os.path.relpath(primitive_path, MODELS_DIR),
                                                  os.path.relpath(mesh_path, MODELS_DIR),
                                                  len(written))]
    try:
        prim = ParsedUrdf(primitive_path)
        meshy = ParsedUrdf(mesh_path)
        check_urdf_structure(prim, mesh_variant=False)
        check_urdf_structure(meshy, mesh_variant=True)
        check_same_kinematics(prim, meshy)
        for name, (filename, _, _) in mesh_assignments().items():
            check(os.path.isfile(resolve_mesh_path(filename)), filename + " missing")
        report.append("URDF structure: %d links, %d joints (%d revolute), visual == collision,"
                      " mesh variant has identical joints and inertials." %
                      (len(prim.links), len(prim.joints),
                       sum(1 for j in prim.joints.values() if j["type"] == "revolute")))
        check_mesh_files(written, report)
        report += home_comment_lines()
        check_home_pose(prim, report)
    except Failure as e:
        print("\n".join(report))
        print("CHECK FAILED: %s" % e)
        return 1
    readme_path = os.path.join(MODELS_DIR, "README.md")
    write_text(readme_path, readme_text(links, joints, report))
    report.append("Wrote README.md.")
    print("\n".join(report))
    print("All checks passed.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
