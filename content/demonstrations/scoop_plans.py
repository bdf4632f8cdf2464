#!/usr/bin/env python3
"""Cup-centre plans of the bundled C4-C5 demonstrations, placed on a module's own disc.

Each demonstration is a plan: a list of scoops (and, for the novices, their mistakes) written
once on a *reference disc* -- the one the bundled modules had when these plans were drawn
(`REFERENCE` below) -- and mapped onto the disc of the module file it is generated for:

- lateral (x): scaled so the widest reference sweep (cup centre 3.6 mm from the middle) ends
  where the cup's outer edge meets the module's lateral annulus (annulus x semi-axis minus the
  cup's outer radius), about the nucleus centre;
- depth (z, anterior +): scaled so the deepest reference scoop (cup centre 3.3 mm behind the
  nucleus centre, its back 0.2 mm past the posterior annulus's inner... edge of the block) keeps
  the same place against the module's posterior annulus: (annulus z semi-axis - cup radius +
  0.2 mm) behind the nucleus centre; above the disc, heights are kept from the disc's front;
- height (y, cranial +): scaled so the cup keeps the same share of the clearance it has between
  the endplates' warning bands (half the disc height - cup radius - 0.3 mm);
- the specimen tray: the wipe keeps its place on the module's tray (world.box) and its depth
  into the tray floor (the curette's own pitch and press: 80 deg, 1.06 mm above the floor for
  the angled 135-degree cup; 65 deg, 0.30 mm for a straight cup);
- time: each scoop is the same eleven moves (blocks of 1.0, 1.2, 1.5, 1.2, 0.6, 1.2, 0.8, 0.8,
  1.2, 0.6, 0.8 s) times the plan's pace.

So when the disc, the window or the curette of a module changes, running scripts/demonstrations
places every pass again on the new anatomy. On the reference disc the mapping is the identity,
and the plans reproduce the cup rows they were drawn with (expert_1 of each module is the
earlier c4c5_expert / c4c5_expert_straight / c4c5_expert_timed, byte for byte).

    python3 scoop_plans.py ../../scenarios/modules/02_c4c5_healthy.json --list
    python3 scoop_plans.py ../../scenarios/modules/02_c4c5_healthy.json expert_2 > expert_2.cup.csv
    python3 scoop_plans.py MODULE.json --write-dir DIR    # every plan: DIR/<name>.cup.csv and
                                                          # DIR/<name>.waypoints.csv
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import c4c5_waypoints  # noqa: E402

# The disc the plans were drawn on (scenarios/modules/02_c4c5_healthy.json before the disc was
# resized): nucleus elliptic cylinder centred at z -0.5 mm, semi-axes 3.5 (x) x 3.0 (z); annulus
# 5.5 x 5.0; disc height 5.9 mm; the 3 mm cup with a 0.4 mm wall; the tray floor at z 6 mm,
# tray centre y -31 mm, far edge y -20 mm.
REFERENCE = {
    "nucleus_cx": 0.0, "nucleus_cz": -0.5, "annulus_a": 5.5, "annulus_b": 5.0,
    "disc_height": 5.9, "cup_r": 1.9, "tray_cx": 0.0, "tray_cy": -31.0, "tray_far_y": -20.0,
    "tray_floor": 6.0,
}
ENDPLATE_WARNING_MM = 0.3   # engine/anatomy/danger_zone.hpp: endplate_warning_m
BLOCKS_S = (1.0, 1.2, 1.5, 1.2, 0.6, 1.2, 0.8, 0.8, 1.2, 0.6, 0.8)


def module_geometry(module):
    """The dimensions the plans are placed by, read from a module file (JSON)."""
    world = module["world"]
    blocks = world["nucleus"]["blocks"]
    materials = {m["name"]: m for m in world["nucleus"]["materials"]}
    target = [b for b in blocks if materials[b["material"]].get("counts_as_target")]
    ring = [b for b in blocks if "hole_semi_axes_mm" in b]
    if not target or not ring:
        raise ValueError("world.nucleus.blocks: expected a target (nucleus) block and an annulus "
                         "block with hole_semi_axes_mm")
    nucleus, annulus = target[0], ring[0]
    for b in (nucleus, annulus):
        if b.get("shape") != "elliptic_cylinder" or b.get("axis") != "y":
            raise ValueError("world.nucleus.blocks: expected elliptic cylinders along y (got %s "
                             "along %s)" % (b.get("shape"), b.get("axis")))
    inst = world["instrument"]
    box = world["box"]
    morph = world.get("anatomy", {}).get("morphometry", {})
    return {
        "nucleus_cx": nucleus["center_mm"][0], "nucleus_cz": nucleus["center_mm"][2],
        "annulus_a": annulus["semi_axes_mm"][0], "annulus_b": annulus["semi_axes_mm"][1],
        "disc_height": morph.get("disc_height_mm", 5.9),
        "cup_r": 0.5 * inst["cup_diameter_mm"] + inst["cup_wall_mm"],
        "tray_cx": 0.5 * (box["inner_min_mm"][0] + box["inner_max_mm"][0]),
        "tray_cy": 0.5 * (box["inner_min_mm"][1] + box["inner_max_mm"][1]),
        "tray_far_y": box["inner_max_mm"][1], "tray_floor": box["inner_min_mm"][2],
        "angled": inst.get("cup_opening_angle_deg", 90) > 90,
        "grip_mm": c4c5_waypoints.cup_to_grip(inst["shaft_length_mm"], inst["cup_diameter_mm"],
                                              inst["cup_wall_mm"]),
        "time_limit_s": module.get("time_limit_s", 0),
        # The left vertebral artery's axis (engine/anatomy/vertebra_generator.cpp: the
        # foramen transversarium lies uncinate_to_foramen beyond the medial uncinate margin,
        # foramen_anterior_offset ahead of the posterior body wall); defaults of docs/anatomy.md.
        "artery_x": 0.5 * morph.get("endplate_width_mm", 16.1) + morph.get("uncinate_to_foramen_mm", 5.0)
                    + 0.5 * morph.get("foramen_transversarium_diameter_mm", 5.5),
        "artery_z": -0.5 * morph.get("body_depth_mm", 16.1) + morph.get("foramen_anterior_offset_mm", 3.0),
    }


class Placement:
    """Maps reference-disc millimetres onto a module's disc (see the module docstring)."""

    def __init__(self, g):
        r = REFERENCE
        self.g = g
        self.sx = (g["annulus_a"] - g["cup_r"]) / (r["annulus_a"] - r["cup_r"])
        self.sz = (g["annulus_b"] - g["cup_r"] + 0.2) / (r["annulus_b"] - r["cup_r"] + 0.2)
        clear = 0.5 * g["disc_height"] - g["cup_r"] - ENDPLATE_WARNING_MM
        clear_ref = 0.5 * r["disc_height"] - r["cup_r"] - ENDPLATE_WARNING_MM
        self.sy = clear / clear_ref
        self.front = g["nucleus_cz"] + g["annulus_b"]
        self.front_ref = r["nucleus_cz"] + r["annulus_b"]

    def x(self, v):  # lateral, in the disc
        return self.g["nucleus_cx"] + (v - REFERENCE["nucleus_cx"]) * self.sx

    def y(self, v):  # height between the endplates
        return v * self.sy

    def z(self, v):  # depth in the disc
        return self.g["nucleus_cz"] + (v - REFERENCE["nucleus_cz"]) * self.sz

    def above(self, v):  # a height above the disc's front
        return self.front + (v - self.front_ref)

    def artery(self, x, y, z):  # millimetres from the left artery's axis (x, z)
        return (self.g["artery_x"] + x, self.y(y), self.g["artery_z"] + z)

    def tray(self, x, y, z):
        r, g = REFERENCE, self.g
        ty = g["tray_far_y"] if y == r["tray_far_y"] else g["tray_cy"] + (y - r["tray_cy"])
        return (g["tray_cx"] + (x - r["tray_cx"]), ty, g["tray_floor"] + (z - r["tray_floor"]))


# --- the moves, in reference millimetres -------------------------------------------------------
# A scoop: (comment, x_start, x_end, y, z): plunge through the window at x_start to depth z,
# sweep to x_end (the cup opens toward the sweep: yaw 0 toward +x, 180 toward -x), withdraw
# straight, wipe on the tray.
def S(what, x0, x1, y, z):
    return ("scoop", what, x0, x1, y, z)


FRONT = S("front of the nucleus", -2.5, 2.0, 0.0, 1.0)
MID_UP = S("middle, upper half", -2.5, 2.0, 0.6, -1.0)
MID_LOW = S("middle, lower half", -2.5, 2.0, -0.45, -1.0)
BACK = S("back of the nucleus", -2.5, 2.0, 0.0, -2.6)
RIGHT_MID = S("right side, middle", 0.5, 3.5, 0.0, -1.0)
RIGHT_BACK = S("right side, back", 0.0, 3.2, 0.0, -3.0)
LEFT_MID = S("left side, middle", -0.5, -3.5, 0.0, -1.5)
VBACK_UP = S("the very back, upper half", -2.0, 2.0, 0.2, -3.8)
VBACK_LOW = S("the very back, lower half, the other way", 2.0, -2.0, -0.2, -3.8)
RIGHT_BACK_LOW = S("right side, back, lower half", 0.0, 3.2, -0.2, -3.5)
RIGHT_MID_DEEP = S("right side, middle depth", 0.5, 3.6, 0.0, -2.0)
LEFT_BACK = S("left side, back", 0.0, -3.2, 0.0, -3.0)
MID_UP_AGAIN = S("middle, upper half again", -2.5, 2.0, 0.3, -1.5)
MID_LOW_AGAIN = S("middle, lower half again, the other way", 2.5, -2.0, -0.45, -1.5)
LEFT_MID_DEEP = S("left side, middle depth", -0.5, -3.6, 0.0, -2.0)
LEFT_BACK_LOW = S("left side, back, lower half", 0.0, -3.2, -0.2, -3.5)
FRONT_OTHER = S("front, the other way", 2.5, -2.0, 0.0, 1.0)
# The straight curette's plan (module 03), drawn with the cup 3.5 mm from the posterior margin.
ST_OTHER_MID = S("the other way (opening -x), what is left in the middle", 2.5, -2.0, 0.0, 0.0)
ST_OTHER_BACK = S("the other way, what is left at the back", 2.5, -2.0, 0.0, -2.6)
ST_FRONT_UP = S("second pass: front, upper half", -2.5, 2.0, 0.3, 0.0)
ST_BACK_LOW_OTHER = S("second pass: back, lower half, the other way", 2.5, -2.0, -0.22, -2.0)
ST_BACK_LOW = S("second pass: back, lower half", -2.5, 2.0, -0.22, -1.8)
ST_MID_UP_OTHER = S("second pass: middle, upper half, the other way", 2.5, -2.0, 0.6, -1.5)
ST_BACK_AGAIN = S("second pass: the back again", -2.5, 2.0, 0.0, -2.6)
ST_FRONT_LOW_OTHER = S("second pass: front, lower half, the other way", 2.5, -2.0, -0.22, 0.5)
ST_MID_UP_AGAIN = S("middle, upper half again", -2.5, 2.0, 0.5, -1.5)
ST_MID_LOW_AGAIN = S("middle, lower half again, the other way", 2.5, -2.0, -0.45, -1.5)

# Mistakes (rows of their own, reference millimetres; see each novice's description).
def DRIFT():
    # Wanders out of the disc and down beside the uncinate process toward the left vertebral
    # artery: (x, z) of these rows are millimetres from the artery's axis (Placement.artery),
    # not from the disc.
    return ("artery_rows", "lateral drift toward the left vertebral artery", [
        (1.0, (-4.0, 0.0, 11.0), (0, 0, 0), "out of the window, up and to the left"),
        (1.2, (-3.0, 0.0, 8.0), (0, 0, 0), "past the lateral edge of the body, in front of the "
                                            "uncinate process"),
        (1.2, (-3.0, 0.0, 3.05), (0, 0, 0), "down beside the uncinate process, toward the artery"),
        (1.5, (-3.0, 0.0, 3.05), (0, 0, 0), "stays there: 0.5 mm from the artery's zone"),
        (1.2, (-3.0, 0.0, 12.0), (0, 0, 0), "back up"),
    ])


def PLUNGE():
    # Plunges through the posterior annulus into the spinal cord / PLL zone and stays 1.5 s.
    return ("rows", "posterior plunge toward the cord", [
        (1.0, (-2.5, 0.0, 12.0), (0, 0, 0), "above the window"),
        (1.2, (-2.5, 0.0, -2.6), (0, 0, 0), "plunge to the back of the nucleus"),
        (0.8, (-2.5, 0.0, -6.8), (0, 0, 0), "on through the posterior annulus: 3 mm too deep"),
        (1.5, (-2.5, 0.0, -6.8), (0, 0, 0), "stays there"),
        (0.8, (-2.5, 0.0, -2.6), (0, 0, 0), "back to the expert's depth"),
        (1.2, (2.0, 0.0, -2.6), (0, 0, 0), "sweep"),
        (1.0, (2.0, 0.0, 14.0), (0, 0, 0), "withdrawal"),
    ])


def LEVER():
    # Levers on the shaft with the cup deep in the disc: the shaft bears on the endplate rims.
    return ("rows", "levering on the shaft against the endplate rims", [
        (1.0, (0.0, 0.0, 12.0), (0, 0, 0), "above the window"),
        (1.2, (0.0, 0.0, -2.0), (0, 0, 0), "plunge into the nucleus"),
        (1.0, (0.0, 0.0, -2.0), (24, 0, 0), "lever: roll 24 deg, the cup pried toward C4"),
        (1.0, (0.0, 0.0, -2.0), (24, 0, 0), "holds the lever"),
        (1.0, (0.0, 0.0, -2.0), (0, 0, 0), "back"),
        (1.0, (0.0, 0.0, -2.0), (-24, 0, 0), "the other way"),
        (1.0, (0.0, 0.0, -2.0), (-24, 0, 0), "holds the lever"),
        (1.0, (0.0, 0.0, -2.0), (0, 0, 0), "back"),
        (1.0, (0.0, 0.0, 14.0), (0, 0, 0), "withdrawal"),
    ])


def SCRAPE():
    # Presses the cup up against the C4 endplate and scrapes along it, front to back and across.
    return ("rows", "scraping the C4 endplate", [
        (1.0, (-2.5, 0.0, 12.0), (0, 0, 0), "above the window"),
        (1.0, (-2.5, 0.0, 0.5), (0, 0, 0), "into the disc"),
        (0.8, (-2.5, 2.4, 0.5), (0, 0, 0), "pressed up into the C4 endplate"),
        (1.5, (2.5, 2.4, 0.5), (0, 0, 0), "scraping across it"),
        (1.2, (2.5, 2.4, -2.5), (0, 0, 0), "and back along it"),
        (1.5, (-2.5, 2.4, -2.5), (0, 0, 0), "and across again"),
        (0.8, (-2.5, 0.0, -2.5), (0, 0, 0), "off the endplate"),
        (1.0, (-2.5, 0.0, 14.0), (0, 0, 0), "withdrawal"),
    ])


def PAUSE(seconds, what):
    return ("pause", what, seconds)


ANGLED_REFERENCE = [FRONT, MID_UP, MID_LOW, BACK, RIGHT_MID, RIGHT_BACK, LEFT_MID, VBACK_UP,
                    VBACK_LOW, RIGHT_BACK_LOW, RIGHT_MID_DEEP, LEFT_BACK, MID_UP_AGAIN,
                    MID_LOW_AGAIN]
STRAIGHT_REFERENCE = [FRONT, MID_UP, MID_LOW, BACK, ST_OTHER_MID, ST_OTHER_BACK, ST_FRONT_UP,
                      ST_BACK_LOW_OTHER, ST_BACK_LOW, ST_MID_UP_OTHER, ST_BACK_AGAIN,
                      ST_FRONT_LOW_OTHER, ST_MID_UP_AGAIN, ST_MID_LOW_AGAIN]

# name -> (description, pace (times the blocks), moves)
ANGLED_EXPERTS_02 = {
    "expert_1": ("the reference plan: four over the middle, eight along the lateral annulus and "
                 "at the very back, the middle again", 0.75, ANGLED_REFERENCE),
    "expert_2": ("sides first: the front, then both lateral gutters, then the middle and the "
                 "back, at a steadier pace", 0.8,
                 [FRONT, RIGHT_MID, LEFT_MID, MID_UP, MID_LOW, RIGHT_BACK, LEFT_BACK, BACK,
                  VBACK_UP, VBACK_LOW, RIGHT_MID_DEEP, LEFT_MID_DEEP, MID_UP_AGAIN]),
    "expert_3": ("back first, slow and deliberate: the middle, then the very back, then the "
                 "sides", 0.85,
                 [FRONT, MID_UP, BACK, VBACK_UP, VBACK_LOW, MID_LOW, RIGHT_BACK, LEFT_BACK,
                  RIGHT_MID_DEEP, LEFT_MID_DEEP, MID_UP_AGAIN, MID_LOW_AGAIN]),
    "expert_4": ("brisk: sixteen quick scoops, alternating sides", 0.65,
                 [FRONT, MID_UP, MID_LOW, BACK, RIGHT_MID, LEFT_MID, RIGHT_BACK, LEFT_BACK,
                  VBACK_UP, VBACK_LOW, RIGHT_MID_DEEP, LEFT_MID_DEEP, RIGHT_BACK_LOW,
                  LEFT_BACK_LOW, MID_UP_AGAIN, MID_LOW_AGAIN]),
    "expert_5": ("both directions: each region swept once toward each side", 0.75,
                 [FRONT, FRONT_OTHER, MID_UP, MID_LOW_AGAIN, BACK, VBACK_LOW, RIGHT_MID,
                  LEFT_MID, RIGHT_BACK, LEFT_BACK, VBACK_UP, RIGHT_MID_DEEP, LEFT_MID_DEEP,
                  MID_UP_AGAIN]),
}
ANGLED_EXPERTS_04 = {
    "expert_1": ("the reference plan's first ten scoops, against the clock", 0.75,
                 ANGLED_REFERENCE[:10]),
    "expert_2": ("eleven quicker scoops: the middle, both sides, the very back", 0.7,
                 [FRONT, MID_UP, MID_LOW, BACK, RIGHT_MID, LEFT_MID, RIGHT_BACK, LEFT_BACK,
                  VBACK_UP, VBACK_LOW, MID_UP_AGAIN]),
    "expert_3": ("nine unhurried scoops, back first", 0.85,
                 [FRONT, MID_UP, BACK, VBACK_UP, VBACK_LOW, MID_LOW, RIGHT_BACK, LEFT_BACK,
                  MID_UP_AGAIN]),
    "expert_4": ("twelve brisk scoops, sides first", 0.62,
                 [FRONT, RIGHT_MID, LEFT_MID, MID_UP, MID_LOW, RIGHT_BACK, LEFT_BACK, BACK,
                  VBACK_UP, VBACK_LOW, RIGHT_MID_DEEP, LEFT_MID_DEEP]),
    "expert_5": ("ten scoops in both directions", 0.78,
                 [FRONT, FRONT_OTHER, MID_UP, MID_LOW_AGAIN, BACK, VBACK_LOW, RIGHT_BACK,
                  LEFT_BACK, VBACK_UP, MID_UP_AGAIN]),
}
STRAIGHT_EXPERTS_03 = {
    "expert_1": ("the reference plan: six over the disc, six more at other heights and depths, "
                 "the middle again", 0.75, STRAIGHT_REFERENCE),
    "expert_2": ("the same scoops, second pass first, at a steadier pace", 0.8,
                 [FRONT, ST_OTHER_MID, MID_UP, ST_BACK_LOW_OTHER, ST_BACK_LOW, MID_LOW, BACK,
                  ST_OTHER_BACK, ST_FRONT_UP, ST_MID_UP_OTHER, ST_BACK_AGAIN,
                  ST_FRONT_LOW_OTHER, ST_MID_UP_AGAIN]),
    "expert_3": ("twelve slow scoops, the back early", 0.85,
                 [FRONT, MID_UP, BACK, ST_OTHER_BACK, MID_LOW, ST_OTHER_MID, ST_BACK_LOW,
                  ST_BACK_LOW_OTHER, ST_FRONT_UP, ST_MID_UP_OTHER, ST_MID_UP_AGAIN,
                  ST_MID_LOW_AGAIN]),
    "expert_4": ("sixteen brisk scoops", 0.65,
                 STRAIGHT_REFERENCE + [ST_OTHER_MID, ST_BACK_LOW]),
    "expert_5": ("alternating directions through the middle", 0.75,
                 [FRONT, FRONT_OTHER, MID_UP, ST_MID_UP_OTHER, MID_LOW, ST_MID_LOW_AGAIN,
                  BACK, ST_OTHER_BACK, ST_FRONT_UP, ST_FRONT_LOW_OTHER, ST_BACK_LOW,
                  ST_BACK_LOW_OTHER, ST_MID_UP_AGAIN, ST_BACK_AGAIN]),
}


def novices(reference, time_limit_s):
    """The same five kinds of error for every anatomical module."""
    # Too slow: the reference plan at a third of the experts' pace with a pause before each
    # scoop; the time limit runs out after a few scoops.
    slow = []
    for i, s in enumerate(reference):
        slow.append(PAUSE(6.0, "hesitates over the window"))
        slow.append(s)
    return {
        "novice_drift": ("one clean scoop, then the cup wanders out of the window to the left, "
                         "past the edge of the vertebral body and down beside the uncinate "
                         "process to 0.5 mm from the left vertebral artery's zone", 0.75,
                         [FRONT, DRIFT()]),
        "novice_plunge": ("one clean scoop, then a plunge 3 mm too deep through the posterior "
                          "annulus into the spinal cord / PLL zone", 0.75, [FRONT, PLUNGE()]),
        "novice_lever": ("one clean scoop, then levering on the shaft (roll 24 deg each way) "
                         "with the cup deep in the disc: the shaft bears on the endplate rims",
                         0.75, [FRONT, LEVER()]),
        "novice_scrape": ("one clean scoop, then the cup pressed against the C4 endplate and "
                          "scraped across and along it", 0.75, [FRONT, SCRAPE()]),
        "novice_slow": ("hesitation: the reference plan at 1.6 times the experts' slowest pace, "
                        "pausing 6 s over the window before each scoop; the time limit "
                        "(%g s) ends it" % time_limit_s, 1.6, slow),
    }


def plans_for(module_path, g):
    name = os.path.splitext(os.path.basename(module_path))[0]
    if name.startswith("03") or not g["angled"]:
        experts, reference = STRAIGHT_EXPERTS_03, STRAIGHT_REFERENCE
    elif name.startswith("04") or g["time_limit_s"] and g["time_limit_s"] < 100:
        experts, reference = ANGLED_EXPERTS_04, ANGLED_REFERENCE
    else:
        experts, reference = ANGLED_EXPERTS_02, ANGLED_REFERENCE
    plans = dict(experts)
    plans.update(novices(reference, g["time_limit_s"]))
    return plans


def fmt(t, cup, rpy, what):
    return "%.2f, %5.2f, %5.2f, %5.2f, %g, %g, %g   # %s" % (t, cup[0], cup[1], cup[2], *rpy, what)


def cup_rows(plan, g):
    """The cup-centre rows (strings, with '#' comments) of one plan on geometry g."""
    description, pace, moves = plan
    p = Placement(g)
    wipe_pitch, press = (80, 1.06) if g["angled"] else (65, 0.30)
    turn = 7.06 if g["angled"] else 8.0        # reference heights above the floor: turn, lift
    lift = 7.06 if g["angled"] else 6.0
    out = []
    t = 0.0
    last = (p.x(0.0), p.y(0.0), p.above(20.0))
    out.append(fmt(t, last, (0, 0, 0), "start, above the field"))
    n = 0

    def row(dt, cup, rpy, what):
        nonlocal t
        t += dt
        out.append(fmt(t, cup, rpy, what))

    for m in moves:
        if g["time_limit_s"] and t >= g["time_limit_s"]:
            break  # the attempt ends at the time limit: no more moves
        if m[0] == "pause":
            row(m[2], last, (0, 0, 0), m[1])
            continue
        n += 1
        b = [x * pace for x in BLOCKS_S]
        if m[0] == "scoop":
            _, what, x0, x1, y, z = m
            yaw = 0 if x1 > x0 else 180
            out.append("# scoop %d: %s" % (n, what))
            row(b[0], (p.x(x0), p.y(y), p.above(12.0)), (0, 0, yaw), "above the window")
            row(b[1], (p.x(x0), p.y(y), p.z(z)), (0, 0, yaw), "plunge into the nucleus")
            row(b[2], (p.x(x1), p.y(y), p.z(z)), (0, 0, yaw),
                "sweep toward the opening: the cup fills")
            row(b[3], (p.x(x1), p.y(y), p.above(14.0)), (0, 0, yaw), "straight withdrawal")
            row(b[4], (p.x(x1), p.y(0.0), p.above(20.0)), (0, 0, yaw), "")
        else:
            kind, what, rows = m
            out.append("# %d: %s" % (n, what))
            for k, (dt, (x, y, z), rpy, note) in enumerate(rows):
                if kind == "artery_rows":
                    cup = p.artery(x, y, z)
                else:
                    inside = z < p.front_ref
                    cup = (p.x(x), p.y(y), p.z(z) if inside else p.above(z))
                row(dt * pace, cup, rpy, note)
            row(b[4], (cup[0], p.y(0.0), p.above(20.0)), (0, 0, 0), "")
        # the wipe on the tray
        row(b[5], p.tray(3.0, -29.0, 20.0 - 6.0 + REFERENCE["tray_floor"]), (0, 0, 0),
            "over the tray")
        row(b[6], p.tray(3.0, -29.0, 6.0 + turn), (0, wipe_pitch, 0),
            "opening turned down (pitch %d)" % wipe_pitch)
        row(b[7], p.tray(3.0, -29.0, 6.0 + press), (0, wipe_pitch, 0),
            "lip pressed 0.5 mm into the tray floor")
        row(b[8], p.tray(0.0, -29.0, 6.0 + press), (0, wipe_pitch, 0), "wipe: drag 3 mm, lip first")
        row(b[9], p.tray(0.0, -29.0, 6.0 + lift), (0, wipe_pitch, 0),
            "lift off")
        row(b[10], p.tray(0.0, -20.0, 20.0), (0, 0, 0), "")
        last = (p.x(0.0), p.y(0.0), p.above(20.0))
    return description, out


def header(name, description, g, module_path):
    return [
        "# %s for %s: %s." % (name, os.path.basename(module_path), description),
        "# Written by content/demonstrations/scoop_plans.py from the module's disc, window, curette",
        "# and tray; do not edit by hand (scripts/demonstrations regenerates it).",
        "# Cup-centre rows for c4c5_waypoints.py: t_s, cup x, y, z (mm), roll, pitch, yaw (deg).",
    ]


def main():
    ap = argparse.ArgumentParser(description="cup-centre plans of the C4-C5 demonstrations")
    ap.add_argument("module", help="module file (scenarios/modules/0[2-4]_*.json)")
    ap.add_argument("plan", nargs="?", help="one plan name (expert_N, novice_KIND)")
    ap.add_argument("--list", action="store_true", help="list the plans for this module")
    ap.add_argument("--write-dir", help="write every plan's .cup.csv and .waypoints.csv here")
    args = ap.parse_args()
    with open(args.module) as f:
        g = module_geometry(json.load(f))
    plans = plans_for(args.module, g)
    if args.list:
        for name, plan in plans.items():
            print("%-14s %s" % (name, plan[0]))
        return 0
    if args.write_dir:
        for name, plan in plans.items():
            description, rows = cup_rows(plan, g)
            lines = header(name, description, g, args.module) + rows
            with open(os.path.join(args.write_dir, name + ".cup.csv"), "w") as f:
                f.write("\n".join(lines) + "\n")
            with open(os.path.join(args.write_dir, name + ".waypoints.csv"), "w") as f:
                f.write("\n".join(c4c5_waypoints.waypoint_lines(lines, g["grip_mm"])) + "\n")
        return 0
    if args.plan not in plans:
        sys.stderr.write("%s: no plan '%s' (expected one of %s)\n"
                         % (args.module, args.plan, ", ".join(plans)))
        return 2
    description, rows = cup_rows(plans[args.plan], g)
    print("\n".join(header(args.plan, description, g, args.module) + rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
