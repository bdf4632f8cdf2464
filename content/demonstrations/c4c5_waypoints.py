#!/usr/bin/env python3
"""Grip waypoints for the C4-C5 demonstration attempts, from cup-centre targets.

An author thinks of where the curette's cup should be; the device drives the grip, 81.9 mm
up the shaft (80 mm shaft + 1.9 mm cup radius, scenarios/modules/0[2-4]_*.json). This tool
turns rows of

    t_s, cup_x_mm, cup_y_mm, cup_z_mm, roll_deg, pitch_deg, yaw_deg[, grip]

(segment frame, docs/anatomy.md: x left, y cranial, z anterior = up) into the waypoint CSV of
`acdr make-trajectory` (docs/trajectory-format.md): grip = cup - R(roll, pitch, yaw) (0, 0, -L),
R applied yaw, then pitch, then roll, as engine/devices/waypoint_path.cpp does. Where the orientation
changes between two rows, intermediate waypoints every 10 degrees keep the cup where the rows
put it (the grip is interpolated linearly, so one long rotation would swing the cup through the
anatomy). Lines starting with '#' are copied as comments. Rows with an eighth value, the grip
(0 open .. 1 closed: a rongeur's jaws), give the waypoints a grip column; then every row needs
one, and the intermediate waypoints interpolate it.

    python3 c4c5_waypoints.py expert_1.cup.csv > expert_1.waypoints.csv
    build/acdr make-trajectory expert_1.waypoints.csv expert_1.csv

(content/demonstrations/scoop_plans.py writes the cup rows of the bundled demonstrations from
the module files and calls this tool's waypoint_lines; scripts/demonstrations runs the lot.)

For another curette, give its geometry (the scenario's instrument keys, mm):

    python3 c4c5_waypoints.py --cup 4 --wall 0.4 --shaft 80 rows.cup.csv

For a rongeur the rows place the middle of its jaws (the instrument's working point; angled
jaws put it off the shaft's axis):

    python3 c4c5_waypoints.py --jaw-length 6 --shaft 80 rows.bite.csv
    python3 c4c5_waypoints.py --jaw-length 6 --jaw-angle 30 --shaft 80 rows.bite.csv
"""
import argparse
import math

L_MM = 81.9  # grip to cup centre of the modules' curette: 80 mm shaft + 1.5 mm cup radius + 0.4 mm wall


def rotation(roll, pitch, yaw):
    r, p, y = (math.radians(a) for a in (roll, pitch, yaw))
    rx = [[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]]
    ry = [[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]]
    rz = [[math.cos(y), -math.sin(y), 0], [math.sin(y), math.cos(y), 0], [0, 0, 1]]
    mul = lambda a, b: [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    return mul(rz, mul(ry, rx))


def grip_row(t, cup, rpy, length, jaw=None, lateral=0.0):
    """The waypoint of a row: the grip placed so that the instrument's point (lateral, 0,
    -length) in its own frame (the cup centre, or the middle of a rongeur's jaws, bent off
    the shaft by `lateral` when they are angled) is at `cup`."""
    rot = rotation(*rpy)
    grip = [cup[i] + length * rot[i][2] for i in range(3)]  # cup - R (0, 0, -L)
    if lateral:
        grip = [grip[i] - lateral * rot[i][0] for i in range(3)]  # and - R (lateral, 0, 0)
    row = "%.3f,%.3f,%.3f,%.3f,%.2f,%.2f,%.2f" % (t, grip[0], grip[1], grip[2], *rpy)
    return row if jaw is None else row + ",%.3f" % jaw


def cup_to_grip(shaft_mm, cup_mm, wall_mm):
    """engine/rigid/instrument.cpp: the cup centre lies shaft + cup/2 + wall below the grip."""
    return shaft_mm + 0.5 * cup_mm + wall_mm


def rongeur_to_grip(shaft_mm, jaw_length_mm, jaw_angle_deg=0.0):
    """engine/rigid/instrument.cpp: the middle of the jaws lies (jaw length / 2) (sin a, 0,
    -cos a) from the shaft's tip, a the jaws' bend toward the instrument's +x (0 straight).
    How far below the grip it lies (mm); rongeur_offset gives how far to the side."""
    return shaft_mm + 0.5 * jaw_length_mm * math.cos(math.radians(jaw_angle_deg))


def rongeur_offset(jaw_length_mm, jaw_angle_deg=0.0):
    """How far to the instrument's +x the middle of angled jaws lies off the shaft's axis (mm)."""
    return 0.5 * jaw_length_mm * math.sin(math.radians(jaw_angle_deg))


def waypoint_lines(lines, length=L_MM, lateral=0.0):
    """The waypoint CSV lines for cup-centre row lines (comments copied); `lateral`: the
    working point's offset to the instrument's +x (angled rongeur jaws, rongeur_offset)."""
    rows, out = [], ["t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg"]
    with_grip = None
    for line in lines:
        line = line.strip()
        if not line:
            continue
        if line.startswith("#"):
            out.append(line)
            continue
        # A row may end in a comment: "t, x, y, z, roll, pitch, yaw[, grip]   # what it does".
        values = [float(v) for v in line.split("#")[0].split(",")]
        if len(values) not in (7, 8):
            raise ValueError("'%s': expected 7 or 8 values (the eighth the grip), got %d"
                             % (line, len(values)))
        if with_grip is None:
            with_grip = len(values) == 8
            if with_grip:
                out[0] += ",grip"
        elif with_grip != (len(values) == 8):
            raise ValueError("'%s': every row needs a grip once one has it" % line)
        t, x, y, z, ro, pi, ya = values[:7]
        jaw = values[7] if with_grip else None
        if rows:
            t0, cup0, rpy0, jaw0 = rows[-1]
            turn = max(abs(a - b) for a, b in zip(rpy0, (ro, pi, ya)))
            steps = int(math.ceil(turn / 10.0))
            for k in range(1, steps):
                f = k / steps
                cup = [c0 + f * (c1 - c0) for c0, c1 in zip(cup0, (x, y, z))]
                rpy = [a0 + f * (a1 - a0) for a0, a1 in zip(rpy0, (ro, pi, ya))]
                out.append(grip_row(t0 + f * (t - t0), cup, rpy, length,
                                    None if jaw is None else jaw0 + f * (jaw - jaw0), lateral))
        rows.append((t, (x, y, z), (ro, pi, ya), jaw))
        out.append(grip_row(t, (x, y, z), (ro, pi, ya), length, jaw, lateral))
    return out


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description="grip waypoints from cup-centre rows")
    ap.add_argument("rows", help="cup-centre CSV: t_s, x, y, z (mm), roll, pitch, yaw (deg)")
    ap.add_argument("--cup", type=float, default=3.0, help="cup_diameter_mm (default 3)")
    ap.add_argument("--wall", type=float, default=0.4, help="cup_wall_mm (default 0.4)")
    ap.add_argument("--shaft", type=float, default=80.0, help="shaft_length_mm (default 80)")
    ap.add_argument("--jaw-length", type=float, help="a rongeur's jaw_length_mm: the rows place "
                    "the middle of its jaws")
    ap.add_argument("--jaw-angle", type=float, default=0.0, help="a rongeur's jaw_angle_deg "
                    "(angled jaws; default 0)")
    args = ap.parse_args()
    length = (rongeur_to_grip(args.shaft, args.jaw_length, args.jaw_angle) if args.jaw_length
              else cup_to_grip(args.shaft, args.cup, args.wall))
    lateral = rongeur_offset(args.jaw_length, args.jaw_angle) if args.jaw_length else 0.0
    with open(args.rows) as f:
        print("\n".join(waypoint_lines(f, length, lateral)))
