#!/usr/bin/env python3
"""Generates arttrack's second robot, a single 7-DoF arm with a two-finger gripper, in
models/ (this script's folder).

Writes:
  arm7.urdf             the nominal robot: the simulator's and the tracker's
  arm7_calibrated.urdf  the same robot with a few joint origins moved by 2-4 mm, as a
                        kinematic calibration of a real arm would find them

Kinematics: the Franka Emika Panda's published modified (Craig) Denavit-Hartenberg
parameters and joint limits (facts from the manufacturer's documentation; no file of
theirs is used). Joint i's frame is placed from link i-1's by
  Rot_x(alpha_{i-1}) Trans_x(a_{i-1}) Rot_z(theta_i) Trans_z(d_i),
i.e. URDF origin xyz = (a, -d sin(alpha), d cos(alpha)), rpy = (alpha, 0, 0), axis z.
Geometry: cylinders, boxes and spheres only (no meshes), roughly the arm's size. No
<inertial> blocks: the simulator derives mass and inertia from the geometry (it says so
in a one-line notice), which is what this robot exercises. The second finger is a
<mimic> of the first. The robot stands on a 0.75 m table; the depth camera is not part
of the URDF, the scene places it in the world (models/arm7_scene.yaml).

Standard library only and deterministic: two runs write byte-identical files. It reads
the files back and checks them (structure, mimic, calibrated variant's differences, the
home pose's grasp point above the table); exits non-zero on failure.
Usage: python3 models/generate_arm7.py
"""

import math
import os
import sys

from generate_robot import (Cylinder, Box, Failure, Joint, Link, ParsedUrdf, check, fmt,
                            fmt_vec, joint_lines, v_norm, v_sub, write_text)

MODELS_DIR = os.path.dirname(os.path.abspath(__file__))
TABLE_TOP_Z = 0.75
P = "arm7_"

# (a_{i-1} m, d_i m, alpha_{i-1} rad, lower rad, upper rad, effort Nm, velocity rad/s)
# for joints 1..7, then the flange (d = 0.107 m along joint 7's axis).
DH = [
    (0.0, 0.333, 0.0, -2.8973, 2.8973, 87, 2.175),
    (0.0, 0.0, -math.pi / 2, -1.7628, 1.7628, 87, 2.175),
    (0.0, 0.316, math.pi / 2, -2.8973, 2.8973, 87, 2.175),
    (0.0825, 0.0, math.pi / 2, -3.0718, -0.0698, 87, 2.175),
    (-0.0825, 0.384, -math.pi / 2, -2.8973, 2.8973, 12, 2.61),
    (0.0, 0.0, math.pi / 2, -0.0175, 3.7525, 12, 2.61),
    (0.088, 0.0, math.pi / 2, -2.8973, 2.8973, 12, 2.61),
]
FLANGE_D = 0.107
HAND_YAW = -math.pi / 4  # the hand sits on the flange turned -45 deg about z
FINGER_Z = 0.0584        # finger joints above the flange, along the hand's z
FINGER_MAX = 0.04        # each finger opens 0..40 mm
EE_Z = 0.1034            # grasp point between the fingertips

# The home pose: the gripper pointing down about 0.5 m in front of the base, above
# the table, both fingers 2 cm open.
HOME = [0.0, 0.25, 0.0, -2.2, 0.0, 2.45, 0.785, 0.02]

# Calibrated variant: joint origin changes (m, in the parent link's frame), of the
# size a kinematic calibration of a real arm finds.
CALIBRATION = {
    "joint2": (0.0, 0.0, 0.003),
    "joint4": (0.003, 0.0, 0.0),
    "joint5": (-0.002, 0.004, 0.0),
    "joint7": (0.002, 0.0, 0.0),
}

MATERIALS = [("arm_white", (0.9, 0.9, 0.9, 1)), ("joint_grey", (0.45, 0.45, 0.48, 1)),
             ("hand_black", (0.12, 0.12, 0.12, 1))]

HALF_PI = math.pi / 2


def link_shapes(i):
    """Link i's shapes in its frame (origin on joint i, z its axis)."""
    w, g = "arm_white", "joint_grey"
    along_y = (HALF_PI, 0, 0)  # a cylinder along the link's y
    return {
        0: [Cylinder(0.075, 0.10, (0, 0, 0.05), material=g),
            Cylinder(0.065, 0.15, (0, 0, 0.175), material=w)],
        1: [Cylinder(0.062, 0.12, (0, 0, -0.09), material=w),
            Cylinder(0.062, 0.13, (0, 0, 0), along_y, material=g)],
        2: [Cylinder(0.058, 0.17, (0, -0.12, 0), along_y, material=w)],
        3: [Cylinder(0.058, 0.11, (0, 0, -0.07), material=w),
            Cylinder(0.055, 0.12, (0.0825, 0, 0), along_y, material=g)],
        4: [Box((0.10, 0.09, 0.10), (-0.045, 0.03, 0), material=w),
            Cylinder(0.05, 0.16, (-0.0825, 0.15, 0), along_y, material=w)],
        5: [Cylinder(0.05, 0.16, (0, 0, -0.12), material=w),
            Cylinder(0.05, 0.11, (0, 0, 0), along_y, material=g)],
        6: [Cylinder(0.045, 0.10, (0, 0, 0), material=g),
            Box((0.13, 0.07, 0.07), (0.06, 0, 0), material=w)],
        7: [Cylinder(0.042, 0.09, (0, 0, 0.055), material=g)],
    }[i]


def build_robot(calibrated=False):
    links = [Link(P + "base")]
    joints = [Joint(P + "mount", "fixed", P + "base", P + "link0", (0, 0, TABLE_TOP_Z))]
    links.append(Link(P + "link0", link_shapes(0)))
    for i, (a, d, alpha, lower, upper, effort, velocity) in enumerate(DH, start=1):
        xyz = [a, -d * math.sin(alpha), d * math.cos(alpha)]
        name = "joint%d" % i
        if calibrated and name in CALIBRATION:
            xyz = [x + dx for x, dx in zip(xyz, CALIBRATION[name])]
        joints.append(Joint(P + name, "revolute", P + "link%d" % (i - 1), P + "link%d" % i, xyz,
                            (alpha, 0, 0), (0, 0, 1), lower, upper, effort, velocity, 0.5))
        links.append(Link(P + "link%d" % i, link_shapes(i)))
    joints.append(Joint(P + "hand_joint", "fixed", P + "link7", P + "hand", (0, 0, FLANGE_D),
                        (0, 0, HAND_YAW)))
    links.append(Link(P + "hand", [Box((0.06, 0.20, 0.05), (0, 0, 0.03), material="hand_black"),
                                   Cylinder(0.04, 0.02, (0, 0, 0.0), material="hand_black")]))
    for k, side in ((1, 1.0), (2, -1.0)):
        joints.append(Joint(P + "finger_joint%d" % k, "prismatic", P + "hand",
                            P + "finger%d" % k, (0, 0, FINGER_Z), axis=(0, side, 0), lower=0.0,
                            upper=FINGER_MAX, effort=70, velocity=0.2, damping=5))
        links.append(Link(P + "finger%d" % k, [Box((0.02, 0.016, 0.05),
                                                   (0, side * 0.018, 0.025),
                                                   material="hand_black")]))
    joints.append(Joint(P + "ee_joint", "fixed", P + "hand", P + "ee", (0, 0, EE_Z)))
    links.append(Link(P + "ee"))
    return links, joints


def write_urdf(path, links, joints, calibrated):
    out = ['<?xml version="1.0"?>', "<!--"]
    out.append("  arttrack arm7: a single 7-DoF arm with a two-finger gripper, from the Franka"
               " Emika Panda's published")
    out.append("  modified DH parameters and joint limits; primitives only, no <inertial>"
               " (the simulator derives them).")
    if calibrated:
        out.append("  CALIBRATED variant: joint origins moved by a few millimetres (%s)." %
                   ", ".join("%s%s +(%s) m" % (P, k, fmt_vec(v)) for k, v in
                             sorted(CALIBRATION.items())))
    out.append("  GENERATED by models/generate_arm7.py; edit that script, not this file.")
    out.append("  Frames: arm7_base at the world origin (z up); arm7_link0 on a %s m table"
               " top; arm7_ee is the grasp point." % fmt(TABLE_TOP_Z))
    out.append("  arm7_finger_joint2 mimics arm7_finger_joint1 (both fingers open together).")
    out.append("  Home configuration (rad): " +
               ", ".join("%s=%s" % (j, fmt(q)) for j, q in zip(movable_names(), HOME)))
    out.append("-->")
    out.append('<robot name="arttrack_arm7">')
    for name, rgba in MATERIALS:
        out.append('  <material name="%s"><color rgba="%s"/></material>' % (name, fmt_vec(rgba, 3)))
    for link in links:
        if not link.shapes:
            out.append('  <link name="%s"/>' % link.name)
            continue
        out.append('  <link name="%s">' % link.name)
        for s in link.shapes:
            for tag in ("visual", "collision"):
                out.append("    <%s>" % tag)
                out.append('      <origin xyz="%s" rpy="%s"/>' % (fmt_vec(s.xyz), fmt_vec(s.rpy)))
                out.append("      <geometry>%s</geometry>" % s.urdf_geometry())
                if tag == "visual":
                    out.append('      <material name="%s"/>' % s.material)
                out.append("    </%s>" % tag)
        out.append("  </link>")
    for j in joints:
        mimic = ['    <mimic joint="%sfinger_joint1" multiplier="1" offset="0"/>' % P]
        out += joint_lines(j, mimic if j.name == P + "finger_joint2" else ())
    out.append("</robot>")
    write_text(path, "\n".join(out) + "\n")


def movable_names():
    return [P + "joint%d" % i for i in range(1, 8)] + [P + "finger_joint1"]


def check_files(nominal, calibrated, report):
    for urdf in (nominal, calibrated):
        check(all(l["inertial"] is None for l in urdf.links.values()), "an <inertial> was written")
        for name, l in urdf.links.items():
            check(l["visual"] == l["collision"], name + ": visual != collision")
    movable = [n for n, j in nominal.joints.items() if j["type"] != "fixed"]
    check(movable == movable_names() + [P + "finger_joint2"], "movable joints: %s" % movable)
    check(list(calibrated.joints) == list(nominal.joints), "variants differ in joints")
    moved = []
    for name in nominal.joints:
        d = v_norm(v_sub(nominal.joints[name]["xyz"], calibrated.joints[name]["xyz"]))
        check(d < 0.005, name + ": calibrated origin moved by more than 5 mm")
        if d > 0:
            moved.append("%s %.1f mm" % (name, d * 1000))
    check(len(moved) == len(CALIBRATION), "calibrated variant moved %s" % moved)
    report.append("Calibrated variant: " + ", ".join(moved) + ".")
    q = dict(zip(movable_names(), HOME))
    for urdf, label in ((nominal, "nominal"), (calibrated, "calibrated")):
        ee = urdf.forward_kinematics(q)[P + "ee"].t
        check(ee[2] > TABLE_TOP_Z + 0.05, "%s home grasp point below the table: %s" % (label, ee))
        report.append("Home grasp point (%s): %s m." % (label, fmt_vec(ee, 4)))


def main():
    paths = {c: os.path.join(MODELS_DIR, "arm7_calibrated.urdf" if c else "arm7.urdf")
             for c in (False, True)}
    for calibrated, path in paths.items():
        links, joints = build_robot(calibrated)
        write_urdf(path, links, joints, calibrated)
    report = ["Wrote arm7.urdf and arm7_calibrated.urdf."]
    try:
        check_files(ParsedUrdf(paths[False]), ParsedUrdf(paths[True]), report)
    except Failure as e:
        print("\n".join(report))
        print("CHECK FAILED: %s" % e)
        return 1
    print("\n".join(report))
    print("All checks passed.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
