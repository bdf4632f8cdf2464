#!/usr/bin/env python3
"""Cup-centre plans of the bundled C4-C5 demonstrations, placed on a module's own disc.

Each demonstration is a plan: a list of scoops (and, for the novices, their mistakes). A scoop
is written in *nucleus units* -- lateral u and depth v as fractions of the module's nucleus
semi-axes about its centre (x = cx + u a, z = cz + v b), the height y in millimetres between
the endplates -- so it lands on the module's own disc, and the cup centre is then kept where
the danger zones and the annulus allow (`Placement`):

- depth: never deeper than the spinal cord / PLL zone's warning band plus the cup's outer radius
  and a margin (`CORD_MARGIN_MM`): the zone's front face is the posterior wall of the bodies
  (half the body depth behind the centre), its warning band 1.5 mm in front of it;
- lateral: no further out than the nucleus's edge at the cup's depth plus `LATERAL_REACH_MM`
  (the cup's wall then bears on the inner annulus, which holds; the vertebral arteries'
  3 mm warning band is more than 5 mm further out);
- the posterior annulus: the cup's outer surface `POSTERIOR_CLEARANCE_MM` short of it (it has
  only the canal behind it and 0.35 mm to the removal region's back: gel driven into it bulges
  it out), the sweep following its curve, and a plunge deeper than the nucleus's centre eased
  from there (`EASE_S` times the pace);
- plunge: through the anterior annulotomy window, the cup 0.1 mm inside its edges;
- height: as written, within the endplates' 0.3 mm warning bands for the 1.9 mm outer radius of
  the modules' cup, with a margin of 0.35 mm above and 0.6 mm below (C5's endplate rises
  toward the uncinate processes): -0.15 <= y <= 0.4 mm on a 5.9 mm disc;
- the specimen tray: the wipe on the module's tray (world.box) with the curette's own pitch
  (80 deg for the angled 135-degree cup, 65 deg for a straight cup), the lip pressed about
  0.35 mm deeper into the floor than the earlier wipe and dragged 10 mm instead of 3, so what sticks to the cup is left on the tray (a 3 mm drag
  left 14 of 31 particles on the cup, this one 9; measured on module 02's front scoop);
- time: each scoop is the same moves (in the disc: 1.0, 1.2, 1.5, 1.2, 0.6 s; the wipe: 1.2,
  0.8, 0.8, 1.6, 0.6, 0.8 s) times the plan's pace.

So when the disc, the window or the curette of a module changes, running scripts/demonstrations
places every pass again on the new anatomy.

    python3 scoop_plans.py ../../scenarios/modules/02_c4c5_healthy.json --list
    python3 scoop_plans.py ../../scenarios/modules/02_c4c5_healthy.json expert_2 > expert_2.cup.csv
    python3 scoop_plans.py MODULE.json --write-dir DIR    # every plan: DIR/<name>.cup.csv and
                                                          # DIR/<name>.waypoints.csv
    python3 scoop_plans.py MODULE.json pulls --moves 'F1,F2,P:0.75:0.6:-0.6' --pace 0.65 \
        --write-dir DIR                                   # a trial plan: DIR/pulls.*.csv
    python3 scoop_plans.py COPY.json bites --moves 'R:0:0.35:-0.6,R:0:-0.35:0.2' --pace 0.6 \
        --write-dir DIR                                   # rongeur bites, on a module copy
                                                          # whose instrument is "rongeur"
                                                          # (docs/anatomy.md)
    python3 scoop_plans.py COPY.json wall --moves 'A:0.52:0.1:-0.314:-25' --pace 0.45 \
        --write-dir DIR                                   # angled bites: the jaws opened above
                                                          # the window and plunged open, on a
                                                          # copy whose rongeur may have angled
                                                          # jaws (jaw_angle_deg; docs/anatomy.md)
    python3 scoop_plans.py MODULE.json wall --instrument 2 --moves 'A:0.52:0.1:-0.314:-25' \
        --pace 0.6 --release-tip-mm 6 --release-pace 1.2 --carry-pace 1.5 --write-dir DIR
                                                          # the same for the tray's third
                                                          # instrument, the bite let go 6 mm
                                                          # above the tray floor, released and
                                                          # carried slower than it is taken
"""
import argparse
import contextlib
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import c4c5_waypoints  # noqa: E402
import join_waypoints  # noqa: E402

PART_GAP_S = 1.0  # the hand's move from one part's last row to the next part's first

ENDPLATE_WARNING_MM = 0.3   # engine/anatomy/danger_zone.hpp: endplate_warning_m
CORD_WARNING_MM = 1.5       # engine/anatomy/danger_zone.hpp: cord_warning_m
CORD_MARGIN_MM = 0.6        # kept between the cup and the cord zone's warning band
LATERAL_REACH_MM = 0.15     # how far the cup centre may pass the nucleus's edge
POSTERIOR_CLEARANCE_MM = 0.8  # kept between the cup and the posterior annulus
# Kept between the cup and the endplates' warning bands: the cup rides up to ~0.3 mm off its
# planned height when it squeezes gel against an endplate (0.11 mm from C5's band in module
# 02's expert_4 with a 0.15 mm margin).
ENDPLATE_MARGIN_MM = 0.35
# And below the middle height, as much again: C5's superior endplate rises laterally into the
# uncinate processes and toward its front rim, where a side scoop at -0.4 mm came 0.14 mm from
# C5's band on its way out (module 02, expert_5).
C5_RISE_MARGIN_MM = 0.25
SCOOP_S = (1.0, 1.2, 1.5, 1.2, 0.6)
WIPE_S = (1.2, 0.8, 0.8, 1.6, 0.6, 0.8)
EASE_S = 1.2                # the last of a deep plunge, eased


def tray_roles(world):
    """Where each kind of instrument lies on the module's tray (`world.instruments`): "cup"
    (a cup curette), "rongeur" (straight jaws) and "angled" (jaws bent by jaw_angle_deg), the
    first of each kind; a module with one instrument has only its own, at 0."""
    tray = world.get("instruments") or [world["instrument"]]
    roles = {}
    for i, inst in enumerate(tray):
        if inst.get("shape") == "rongeur":
            role = "angled" if inst.get("jaw_angle_deg", 0.0) else "rongeur"
        else:
            role = "cup"
        roles.setdefault(role, i)
    return roles


def module_geometry(module, instrument=0):
    """The dimensions the plans are placed by, read from a module file (JSON), for the
    instrument at that place on its tray (`world.instruments`; 0 also for `world.instrument`)."""
    world = module["world"]
    blocks = world["nucleus"]["blocks"]
    materials = {m["name"]: m for m in world["nucleus"]["materials"]}
    target = [b for b in blocks if materials[b["material"]].get("counts_as_target")]
    if not target:
        raise ValueError("world.nucleus.blocks: expected a target (nucleus) block")
    nucleus = target[0]
    if nucleus.get("shape") != "elliptic_cylinder" or nucleus.get("axis") != "y":
        raise ValueError("world.nucleus.blocks: expected an elliptic cylinder along y for the "
                         "nucleus (got %s along %s)" % (nucleus.get("shape"), nucleus.get("axis")))
    ring = [b for b in blocks if "cutout_min_mm" in b]
    window = (0.5 * (ring[0]["cutout_max_mm"][0] - ring[0]["cutout_min_mm"][0]) if ring
              else nucleus["semi_axes_mm"][0])
    tray = world.get("instruments") or [world["instrument"]]
    if not 0 <= instrument < len(tray):
        raise ValueError("instrument %d: the module's tray has %d (0 to %d)"
                         % (instrument, len(tray), len(tray) - 1))
    inst = tray[instrument]
    box = world["box"]
    morph = world.get("anatomy", {}).get("morphometry", {})
    jaw = None
    if inst.get("shape") == "rongeur":
        # engine/rigid/instrument_config.hpp defaults
        jaw = {"length": inst.get("jaw_length_mm", 6.0), "width": inst.get("jaw_width_mm", 3.0),
               "depth": inst.get("jaw_depth_mm", 1.0), "wall": inst.get("jaw_wall_mm", 0.4),
               "opening_deg": inst.get("jaw_opening_angle_deg", 50.0),
               "angle_deg": inst.get("jaw_angle_deg", 0.0)}
    return {
        "jaw": jaw,
        "nucleus_cx": nucleus["center_mm"][0], "nucleus_cz": nucleus["center_mm"][2],
        "nucleus_a": nucleus["semi_axes_mm"][0], "nucleus_b": nucleus["semi_axes_mm"][1],
        "window_half": window,  # half the width of the anterior annulotomy window
        "disc_height": morph.get("disc_height_mm", 5.9),
        # a rongeur's closed jaws stand depth + wall off the shaft's axis
        "cup_r": (jaw["depth"] + jaw["wall"] if jaw else
                  0.5 * inst["cup_diameter_mm"] + inst["cup_wall_mm"]),
        "tray_cx": 0.5 * (box["inner_min_mm"][0] + box["inner_max_mm"][0]),
        "tray_cy": 0.5 * (box["inner_min_mm"][1] + box["inner_max_mm"][1]),
        "tray_far_y": box["inner_max_mm"][1], "tray_floor": box["inner_min_mm"][2],
        "angled": inst.get("cup_opening_angle_deg", 90) > 90,
        "grip_mm": (c4c5_waypoints.rongeur_to_grip(inst["shaft_length_mm"], jaw["length"],
                                                   jaw["angle_deg"]) if jaw
                    else c4c5_waypoints.cup_to_grip(inst["shaft_length_mm"],
                                                    inst["cup_diameter_mm"], inst["cup_wall_mm"])),
        # angled jaws: their middle off the shaft's axis, toward the instrument's +x
        "grip_lateral_mm": (c4c5_waypoints.rongeur_offset(jaw["length"], jaw["angle_deg"]) if jaw
                            else 0.0),
        "shaft_length_mm": inst["shaft_length_mm"],
        "shaft_r": 0.5 * inst.get("shaft_diameter_mm", 2.0),
        "time_limit_s": module.get("time_limit_s", 0),
        "roles": tray_roles(world),
        "nucleus_viscosity_Pa_s": materials[nucleus["material"]].get("viscosity_Pa_s", 300.0),
        # The virtual coupling (engine/rigid/instrument_config.hpp defaults): what a hand's push
        # on the grip and its turn of the stylus become at the cup.
        "coupling_N_m": world.get("coupling", {}).get("stiffness_N_m", 500.0),
        "coupling_Nm_rad": world.get("coupling", {}).get("rot_stiffness_Nm_rad", 0.5),
        # The posterior wall of the bodies (engine/anatomy/vertebra_generator.cpp: half the body
        # depth behind the centre), the front face of the spinal cord / PLL zone.
        "body_back_z": -0.5 * morph.get("body_depth_mm", 16.1),
        "body_front_z": 0.5 * morph.get("body_depth_mm", 16.1),
        # The left vertebral artery's axis (the foramen transversarium lies uncinate_to_foramen
        # beyond the medial uncinate margin, foramen_anterior_offset ahead of the posterior body
        # wall); defaults of docs/anatomy.md.
        "artery_x": 0.5 * morph.get("endplate_width_mm", 16.1) + morph.get("uncinate_to_foramen_mm", 5.0)
                    + 0.5 * morph.get("foramen_transversarium_diameter_mm", 5.5),
        "artery_z": -0.5 * morph.get("body_depth_mm", 16.1) + morph.get("foramen_anterior_offset_mm", 3.0),
    }


class Placement:
    """Puts nucleus units and landmarks into the module's millimetres (module docstring)."""

    def __init__(self, g):
        self.g = g
        self.z_min = g["body_back_z"] + CORD_WARNING_MM + g["cup_r"] + CORD_MARGIN_MM
        self.y_max = 0.5 * g["disc_height"] - ENDPLATE_WARNING_MM - g["cup_r"] - ENDPLATE_MARGIN_MM
        self.window = g["window_half"] - g["cup_r"] - 0.1
        self.ease_from = g["nucleus_cz"]

    def floor(self, x):
        """The deepest cup centre at lateral x: the cup's outer surface `POSTERIOR_CLEARANCE_MM`
        short of the posterior annulus (a deeper plunge pushes the gel against it and bulges
        it 0.35 mm backward, out of the removal region, toward the canal), and out of the
        cord zone's warning band."""
        g = self.g
        s = (x - g["nucleus_cx"]) / g["nucleus_a"]
        edge = g["nucleus_cz"] - g["nucleus_b"] * math.sqrt(max(0.0, 1.0 - s * s))
        return max(edge + g["cup_r"] + POSTERIOR_CLEARANCE_MM, self.z_min)

    def depth(self, v):  # v: fraction of the nucleus's depth semi-axis, + anterior
        g = self.g
        return max(g["nucleus_cz"] + v * g["nucleus_b"], self.z_min)

    def reach(self, z):  # the farthest lateral cup centre at depth z
        g = self.g
        s = (z - g["nucleus_cz"]) / g["nucleus_b"]
        return g["nucleus_a"] * math.sqrt(max(0.0, 1.0 - s * s)) + LATERAL_REACH_MM

    def lateral(self, u, z):
        g = self.g
        r = self.reach(z)
        return g["nucleus_cx"] + max(-r, min(r, u * g["nucleus_a"]))

    def height(self, y):
        # The straight cup opens sideways and its rim hangs lower: in 03's stiff gel it came
        # within 0.14-0.29 mm of C5's band from -0.15 mm, so it stays at or above the middle.
        low = self.y_max - C5_RISE_MARGIN_MM if self.g["angled"] else 0.0
        return max(-low, min(self.y_max, y))

    def above(self, h):  # h mm above the front of the bodies
        return self.g["body_front_z"] + h

    def press(self, force_N):
        """The cup-centre height, the rise of its depth and the roll (deg) of a hand that presses
        the cup down on the middle of the C5 endplate with force_N, the shaft upright: the grip
        pushed force_N / ks past where the cup stops, and the stylus rolled so the rotational
        coupling carries the moment force_N * L of that push about the cup (kr * roll =
        force_N * L), as a wrist does. Without the roll the weak rotational coupling
        (0.5 N*m/rad) lets the shaft tilt, and the cup bears with only ks kr / (kr + ks L^2),
        some 65 N/m, of the push. The grip stays at the upright shaft's height (the rolled
        pose's cup row is L (1 - cos roll) higher, else the coupling would push the cup toward
        the back of the disc). The cup row is where that pose would put the cup if nothing
        stopped it."""
        g = self.g
        roll = force_N * g["grip_mm"] * 1e-3 / g["coupling_Nm_rad"]
        touch = 0.5 * g["disc_height"] - g["cup_r"]  # the cup's bottom on the endplate's middle
        y = touch + 1e3 * force_N / g["coupling_N_m"] + g["grip_mm"] * math.sin(roll)
        return -y, g["grip_mm"] * (1.0 - math.cos(roll)), -math.degrees(roll)

    def artery(self, x, y, z):  # millimetres from the left artery's axis (x, z)
        return (self.g["artery_x"] + x, y, self.g["artery_z"] + z)

    def tray(self, x, dy, dz):  # x from the tray's centre line, dy from its centre, dz above its floor
        g = self.g
        return (g["tray_cx"] + x, g["tray_cy"] + dy, g["tray_floor"] + dz)


# --- the moves -----------------------------------------------------------------------------------
# A scoop: (comment, u_start, u_end, y, v): plunge through the window at u_start to depth v,
# sweep to u_end (the cup opens toward the sweep: yaw 0 toward +x, 180 toward -x), withdraw
# straight, wipe on the tray. +x is the patient's left.
def S(what, u0, u1, y, v):
    return ("scoop", what, u0, u1, y, v)


# A pull, as surgeons clear the disc space: plunge through the window to depth v (the cup's back
# first), out to the lane at u along the back, then pull straight toward the surgeon along the
# lane and out through the window. The angled cup's opening leans 45 deg toward the handle, so
# it faces the lane's side and the pull; pitch (deg) turns it further toward the pull, the shaft
# leaning toward the other side. A straight cup opens toward the lane's side. Measured on module
# 02 and not used by the bundled plans (docs/anatomy.md, "The cohorts": what the plans cannot).
def P(what, u, y, v, pitch=0):
    return ("pull", what, u, y, v, pitch)


# A bite with a pituitary rongeur (the module's instrument "rongeur"): the jaws closed through
# the window, to the lane at u with their tips at depth v (fractions of the nucleus's semi-axes,
# as the scoops), opened there by `opening` (a fraction of their full opening, narrowed so the
# open tips stay within JAW_LATERAL_REACH_MM of the nucleus's edge), closed on the gel, drawn
# out and opened over the tray. y: the jaws' middle, mm. Lanes beyond what the closed jaws can
# pass through the window straight are reached by tilting the shaft about the window.
def R(what, u, y, v, opening=1.0):
    return ("bite", what, u, y, v, opening)


# An angled bite, with a rongeur whose jaws are bent off its shaft (jaw_angle_deg): the jaws
# opened above the window, then in along the shaft with them open, so a plate slides down
# between the gel and the annulus instead of pushing the gel ahead of closed jaws; closed
# there, drawn out along the shaft and opened over the tray. The jaws' middle (closed) at u, v
# (nucleus units) and y (mm); axis: the jaws' axis in the disc, deg from the shaft's straight
# line into it (-z), + toward +x. The instrument is rolled so its bend leans the jaws the way
# the axis does (yaw 0 for +x, 180 for -x) and the shaft leans what the bend leaves; opening:
# the fraction of the full opening. A shaft that would not pass the window is refused.
def A(what, u, y, v, axis, opening=1.0):
    return ("angled_bite", what, u, y, v, axis, opening)


JAW_LATERAL_REACH_MM = 0.5   # the open jaws' tips past the nucleus's edge, at most
TIP_CLEARANCE_MM = 0.3       # the jaws' tips in front of the posterior edge of the nucleus
BITE_S = (0.8, 1.0, 0.3, 0.15, 0.35, 0.1, 1.0, 0.5)   # window, plunge, open, wait, close,
                                                      # wait, withdraw, up
RELEASE_S = (1.0, 0.5, 0.3, 0.3, 0.5, 0.3)            # tray, down, open, wait, up, close
RELEASE_TIP_MM = 0.5         # the jaws' tips above the tray's floor when they open there
ANGLED_BACK_SPAN = 0.9       # the angled bites' tips kept off the posterior annulus this far out
# How far in front of the nucleus's posterior edge the open tips of an angled bite stay there:
# negative lets them past it, into the posterior annulus. The open plates slice into it edge
# on; measured on module 02 (docs/anatomy.md), tips 0.3 mm in front removed 3 points less
# (76.2 % against 79.3 %) with as much annulus out of the region (105 against 108 mm3).
ANGLED_TIP_CLEARANCE_MM = -1.0
# An angled bite's load hangs further below the tips: held particles pressed into the floor
# overloaded the shaft when the jaws let them go with the tips 0.5 mm above it (docs/anatomy.md).
ANGLED_RELEASE_TIP_MM = 3.0


# The front band (v 0.55, rows 2-4 mm in front of the centre), the middle (v 0), the back
# (v -0.45: deeper, the cup would press the posterior annulus, see Placement.floor), the sides.
F1 = S("front, from the right", -0.55, 0.1, 0.0, 0.55)
F2 = S("front, from the left", 0.55, -0.1, 0.0, 0.55)
F_UP = S("front, upper half", -0.55, 0.4, 0.5, 0.5)
F_LOW = S("front, lower half, from the left", 0.55, -0.4, -0.45, 0.5)
M1 = S("middle, upper half, to the left", 0.0, 0.65, 0.55, 0.0)
M2 = S("middle, lower half, to the right", 0.0, -0.65, -0.45, 0.0)
M3 = S("middle, lower half, to the left", 0.0, 0.65, -0.45, 0.0)
M4 = S("middle, upper half, to the right", 0.0, -0.65, 0.55, 0.0)
L1 = S("left side (+x), middle", 0.45, 0.97, 0.0, -0.05)
L2 = S("right side (-x), middle", -0.45, -0.97, 0.0, -0.05)
LF1 = S("left side, front", 0.3, 0.9, 0.0, 0.3)
LF2 = S("right side, front", -0.3, -0.9, 0.0, 0.3)
LB1 = S("left side, back", 0.3, 0.85, 0.0, -0.3)
LB2 = S("right side, back", -0.3, -0.85, 0.0, -0.3)
B1 = S("back, upper half, to the left", 0.0, 0.6, 0.4, -0.45)
B2 = S("back, lower half, to the right", 0.0, -0.6, -0.4, -0.45)
B3 = S("back, lower half, to the left", 0.0, 0.6, -0.4, -0.45)
B4 = S("back, upper half, to the right", 0.0, -0.6, 0.4, -0.45)


# Mistakes (rows of their own in module millimetres; see each novice's description).
def DRIFT():
    # Wanders out of the disc and down beside the uncinate process toward the left vertebral
    # artery: (x, z) of these rows are millimetres from the artery's axis (Placement.artery).
    return ("artery_rows", "lateral drift toward the left vertebral artery", [
        (1.0, (-4.0, 0.0, 11.0), (0, 0, 0), "out of the window, up and to the left"),
        (1.2, (-3.0, 0.0, 8.0), (0, 0, 0), "past the lateral edge of the body, in front of the "
                                            "uncinate process"),
        (1.2, (-3.0, 0.0, 3.05), (0, 0, 0), "down beside the uncinate process, toward the artery"),
        (1.5, (-3.0, 0.0, 3.05), (0, 0, 0), "stays there: 0.5 mm from the artery's zone"),
        (1.2, (-3.0, 0.0, 12.0), (0, 0, 0), "back up"),
    ])


def PLUNGE():
    # Plunges through the posterior annulus into the spinal cord / PLL zone and stays 1.5 s:
    # ("cord", dz) rows are dz mm in front of the posterior body wall.
    return ("cord_rows", "posterior plunge toward the cord", [
        (1.0, (-0.5, 0.0, None), (0, 0, 0), "above the window"),
        (1.2, (-0.5, 0.0, 4.6), (0, 0, 0), "plunge to the back of the nucleus"),
        (0.8, (-0.5, 0.0, 0.4), (0, 0, 0), "on through the posterior annulus: the cup's back "
                                            "1.5 mm into the cord zone"),
        (1.5, (-0.5, 0.0, 0.4), (0, 0, 0), "stays there"),
        (0.8, (-0.5, 0.0, 4.6), (0, 0, 0), "back to the expert's depth"),
        (1.2, (0.4, 0.0, 4.6), (0, 0, 0), "sweep"),
        (1.0, (0.4, 0.0, None), (0, 0, 0), "withdrawal"),
    ])


def LEVER():
    # Levers on the shaft with the cup deep in the disc: the shaft bears on the endplate rims.
    return ("rows", "levering on the shaft against the endplate rims", [
        (1.0, (0.0, 0.0, None), (0, 0, 0), "above the window"),
        (1.2, (0.0, 0.0, -0.4), (0, 0, 0), "plunge into the nucleus"),
        (1.0, (0.0, 0.0, -0.4), (24, 0, 0), "lever: roll 24 deg, the cup pried toward C4"),
        (1.0, (0.0, 0.0, -0.4), (24, 0, 0), "holds the lever"),
        (1.0, (0.0, 0.0, -0.4), (0, 0, 0), "back"),
        (1.0, (0.0, 0.0, -0.4), (-24, 0, 0), "the other way"),
        (1.0, (0.0, 0.0, -0.4), (-24, 0, 0), "holds the lever"),
        (1.0, (0.0, 0.0, -0.4), (0, 0, 0), "back"),
        (1.0, (0.0, 0.0, None), (0, 0, 0), "withdrawal"),
    ])


SCRAPE_FORCE_N = 1.5  # what the novice presses the cup into the endplate with


def SCRAPE():
    # Presses the cup down through the cartilage into the C5 endplate with SCRAPE_FORCE_N and
    # drags it along and across the endplate's middle: rows with "press" for y are pressed
    # (Placement.press). C5's superior endplate is a saddle, lowest in the middle, so the cup
    # pressed into it stays there; pressed up into C4's inferior endplate, convex from side to
    # side, it slides off sideways (it did: out past the uncinate process).
    return ("press_rows", "scraping the C5 endplate", [
        (1.0, (-0.3, None, None), "above the window"),
        (1.0, (-0.3, 0.0, 0.2), "into the disc"),
        (0.8, (-0.3, "press", 0.2), "pressed down through the cartilage into the C5 endplate"),
        (1.5, (-0.3, "press", -0.45), "scraping along it, front to back"),
        (0.8, (0.3, "press", -0.45), "across"),
        (1.5, (0.3, "press", 0.2), "and along it again, back to front"),
        (0.8, (0.3, 0.0, 0.2), "off the endplate"),
        (1.0, (0.3, None, None), "withdrawal"),
    ])


def PAUSE(seconds, what):
    return ("pause", what, seconds)


# name -> (description, pace (times the blocks), moves). A scoop and its wipe take 11.3 s times
# the pace; each plan ends a few seconds before its module's time limit.
REFERENCE = [F1, F2, M1, M2, M3, M4, L1, L2, B1, B2, LB1, LB2, B3, B4]
EXPERTS_120 = {
    "expert_1": ("the reference plan: the front from each side, the middle in both halves and "
                 "both directions, both sides, then the back, 14 scoops", 0.65, REFERENCE),
    "expert_2": ("the front and the middle, the sides at the middle and the back, then the "
                 "back and the front's upper half, 13 scoops at a steadier pace", 0.7,
                 [F1, F2, M1, M2, M4, M3, L1, L2, LB1, LB2, B1, B2, F_UP]),
    "expert_3": ("front to back in three rows, unhurried, 12 scoops", 0.75,
                 [F1, M1, B1, F2, M2, B2, L1, L2, M3, B3, M4, B4]),
    "expert_4": ("brisk: 16 quick scoops", 0.56,
                 [F1, F2, M1, M2, L1, L2, B1, B2, M3, M4, LB1, LB2, B3, B4, F_UP, F_LOW]),
    "expert_5": ("upper half, then lower half, 13 scoops", 0.68,
                 [F_UP, F_LOW, M1, M4, B1, B4, L1, L2, M2, M3, B2, B3, LF1]),
}
EXPERTS_90 = {
    "expert_1": ("the reference plan's first eleven scoops, against the clock", 0.62,
                 REFERENCE[:11]),
    "expert_2": ("the front and the middle, the sides, the back, twelve quicker scoops", 0.58,
                 [F1, F2, M1, M2, M4, M3, L1, L2, LB1, LB2, B1, B2]),
    "expert_3": ("front to back, nine unhurried scoops", 0.75,
                 [F1, M1, B1, F2, M2, B2, L1, L2, M3]),
    "expert_4": ("twelve brisk scoops", 0.56,
                 [F1, F2, M1, M2, L1, L2, B1, B2, M3, M4, LB1, LB2]),
    "expert_5": ("upper half, then lower half, ten scoops", 0.7,
                 [F_UP, F_LOW, M1, M4, B1, B4, L1, L2, M2, M3]),
}


# The degenerated nucleus (module 03: 3000 Pa*s, ten times the healthy gel) drags on the cup ten
# times as hard: at the paces above every expert warned of the shaft's overload (0.31-0.45 N*m
# against the 0.196 N*m warning), at pace 1.0 still 5 times (0.223 N*m); at 1.5 the first eight
# scoops of expert_2 peaked at 0.154 N*m. So in a stiff nucleus the experts take their time and
# fewer scoops, mostly in the lower half: the stiff gel lifts the cup, and the reference plan's
# upper-half scoops came within 0.27 mm of C4's endplate (its warning band is 0.3 mm).
EXPERTS_VISCOUS = {
    "expert_1": ("the front, the lower half of the middle and the sides, six unhurried scoops "
                 "in the stiff gel", 1.5, [F1, F2, M2, M3, L1, L2]),
    "expert_2": ("the front, the middle and the sides, six scoops", 1.45,
                 [F1, F2, M1, M2, L1, L2]),
    "expert_3": ("front to back in two rows, the lower half, six scoops", 1.5,
                 [F1, M2, B2, F2, M3, B3]),
    "expert_4": ("seven scoops, the quickest the stiff gel allows", 1.45,
                 [F1, F2, M2, M3, L1, L2, LF1]),
    "expert_5": ("the lower half, front to back, then a side, six scoops", 1.55,
                 [F_LOW, M2, M3, B2, B3, LB1]),
}
VISCOUS_PA_S = 1000.0  # a target gel above this gets EXPERTS_VISCOUS


# With rongeurs on the tray beside the cup (a straight pituitary rongeur and one whose jaws are
# angled 30 deg) and the posterior longitudinal ligament behind the disc, the experts bite the
# nucleus out in rounds (docs/anatomy.md, "The tray's experts"), each round the same four kinds
# of bite:
# - the angled jaws opened above the window and slid in open along each side wall, in the upper
#   and the lower half (WALL), or higher and lower still (WALL_WIDE; WALL_WIDE_FRONT with the
#   tips further forward); they take the sides the straight jaws cannot reach through the window;
# - the straight jaws down the middle, in the upper and the lower half, and across the back from
#   each side (MIDDLE), or in front (FRONT_MIDDLE).
WALL = [A("the left wall, upper half", 0.52, 0.1, -0.314, -25),
        A("the right wall, upper half", -0.52, 0.1, -0.314, 25),
        A("the left wall, lower half", 0.52, -0.4, -0.314, -25),
        A("the right wall, lower half", -0.52, -0.4, -0.314, 25)]
WALL_WIDE = [A("the left wall, high", 0.52, 0.4, -0.314, -25),
             A("the right wall, high", -0.52, 0.4, -0.314, 25),
             A("the left wall, low", 0.52, -0.6, -0.314, -25),
             A("the right wall, low", -0.52, -0.6, -0.314, 25)]
WALL_WIDE_FRONT = [A("the left wall, high, further forward", 0.52, 0.4, -0.15, -25),
                   A("the right wall, high, further forward", -0.52, 0.4, -0.15, 25),
                   A("the left wall, low, further forward", 0.52, -0.6, -0.15, -25),
                   A("the right wall, low, further forward", -0.52, -0.6, -0.15, 25)]
MIDDLE = [A("the middle, upper half, to the back", 0, 0.3, -0.42, 0),
          A("the middle, lower half, to the back", 0, -0.3, -0.42, 0),
          A("the back, from the right", -0.35, 0, -0.3, 0),
          A("the back, from the left", 0.35, 0, -0.3, 0)]
FRONT_MIDDLE = [A("the middle, upper half, in front", 0, 0.3, 0, 0),
                A("the middle, lower half, in front", 0, -0.3, 0, 0),
                A("the front, right", -0.4, 0, 0.3, 0),
                A("the front, left", 0.4, 0, 0.3, 0)]



def bite_round(wall, middle, angled=None, straight=None):
    """One round of bites: the angled jaws along the side walls, then the straight jaws down the
    middle; `angled` and `straight` the two parts' settings (part_settings), if any."""
    return [("angled", wall, angled or {}), ("rongeur", middle, straight or {})]


# (description, pace, parts): each part (the tray's kind of instrument, its moves[, settings])
# follows the one before, the instrument exchanged in between (join_waypoints.py); settings
# override the generator's release and carry options for that part (part_settings).
EXPERTS_TRAY = {
    "expert_1": ("two rounds: the side walls with the angled rongeur, the middle and the back "
                 "with the straight one, then the walls wider and the middle again", 0.5,
                 bite_round(WALL, MIDDLE) + bite_round(WALL_WIDE, MIDDLE)),
    "expert_2": ("two rounds, the second round's wall bites further forward, a little slower",
                 0.55, bite_round(WALL, MIDDLE) + bite_round(WALL_WIDE_FRONT, MIDDLE)),
    "expert_3": ("brisk: the walls and the middle twice, then the walls wider", 0.45,
                 bite_round(WALL, MIDDLE) * 2 + [("angled", WALL_WIDE)]),
    "expert_4": ("brisk: two rounds, then the front of the middle", 0.45,
                 bite_round(WALL, MIDDLE) + bite_round(WALL_WIDE, MIDDLE)
                 + [("rongeur", FRONT_MIDDLE)]),
    "expert_5": ("unhurried: the walls wide first, the middle, then the walls and the middle",
                 0.6, bite_round(WALL_WIDE, MIDDLE) + bite_round(WALL, MIDDLE)),
}

# In module 03's stiff gel (3,000 Pa*s) the bites themselves are clean at pace 0.6. A held lump
# is drawn out and carried to the tray slowly (pace 1.5 whatever the plan's pace): carried at
# the plan's pace the jaws lose part of it on the way (74.7-76.2 % removed against 77.5-78.4 %,
# docs/performance.md, session 17). The angled jaws let their bites go 6 mm above the tray floor,
# the straight jaws 8 mm above it, at the plan's pace: since the gel film slides on jaws opening
# over the tray, a release no longer needs to be slow (before, a release at the plan's pace
# overloaded the shaft; docs/anatomy.md, "The tray's experts").
ANGLED_STIFF = {"release_tip_mm": 6.0}
STRAIGHT_STIFF = {"release_tip_mm": 8.0, "carry_pace": 1.5}
MIDDLE_BACK_HALF_OPEN = MIDDLE[:2] + [
    A("the back, from the right, the jaws opened 0.6", -0.35, 0, -0.3, 0, 0.6),
    A("the back, from the left, the jaws opened 0.6", 0.35, 0, -0.3, 0, 0.6)]
WALL_WIDE_LOW_HALF_OPEN = WALL_WIDE[:2] + [
    A("the left wall, low, the jaws opened 0.6", 0.52, -0.6, -0.314, -25, 0.6),
    A("the right wall, low, the jaws opened 0.6", -0.52, -0.6, -0.314, 25, 0.6)]


def stiff_round(wall, middle, straight=STRAIGHT_STIFF):
    """A round of bites in the stiff gel, each carried out and let go slowly."""
    return bite_round(wall, middle, ANGLED_STIFF, straight)


# What two rounds leave in the stiff gel (expert_1, 71 of 324 particles; docs/performance.md,
# session 17): the band along the back, the top layer against C4's cartilage and the lateral
# edges. A third round goes after the first two with the angled jaws, to the back along both
# side walls at three heights (BACK_BAND) and along the walls high against C4 (AGAINST_C4),
# then one straight bite to the back of the middle (BACK_MIDDLE); module 03 allows 150 s for it.
def both_walls(where, y, v):
    """Angled bites along the left and the right side wall (lanes at u +-0.52, the jaws' axis
    25 deg toward the wall), the jaws' middle at y (mm) and depth v."""
    return [A("the left wall, " + where, 0.52, y, v, -25),
            A("the right wall, " + where, -0.52, y, v, 25)]


BACK_BAND_MIDDLE = both_walls("to the back", -0.1, -0.55)
BACK_BAND_HIGH = both_walls("to the back, high", 0.4, -0.55)
BACK_BAND_LOW = both_walls("to the back, low", -0.6, -0.55)
AGAINST_C4 = both_walls("against C4", 1.0, -0.314)
BACK_MIDDLE = [A("the back, middle, upper half", 0, 0.3, -0.6, 0)]


def third_round(angled_moves):
    """The third round in the stiff gel: the angled bites given, then the back of the middle."""
    return [("angled", angled_moves, ANGLED_STIFF), ("rongeur", BACK_MIDDLE, STRAIGHT_STIFF)]


# The first two rounds most experts share, and the third round of two of them.
TWO_STIFF_ROUNDS = stiff_round(WALL, MIDDLE) + stiff_round(WALL_WIDE, MIDDLE)
THIRD_ROUND_MIDDLE_FIRST = third_round(BACK_BAND_MIDDLE + AGAINST_C4 + BACK_BAND_LOW
                                       + BACK_BAND_HIGH)

EXPERTS_VISCOUS_TRAY = {
    "expert_1": ("three rounds of bites in the stiff gel: the walls, the middle and the back, the "
                 "walls wider, the middle; then the back band and the walls against C4; each "
                 "bite carried out slowly", 0.6, TWO_STIFF_ROUNDS + THIRD_ROUND_MIDDLE_FIRST),
    "expert_2": ("the same first two rounds, the third starting high at the back and ending "
                 "against C4", 0.6,
                 TWO_STIFF_ROUNDS
                 + third_round(BACK_BAND_HIGH + BACK_BAND_MIDDLE + BACK_BAND_LOW + AGAINST_C4)),
    "expert_3": ("the walls and the middle twice, the same walls both times, then the back band "
                 "and the walls against C4", 0.6,
                 stiff_round(WALL, MIDDLE) * 2 + THIRD_ROUND_MIDDLE_FIRST),
    "expert_4": ("three rounds, the second's last bites at the back with the jaws opened only "
                 "0.6, the walls against C4 last", 0.6,
                 stiff_round(WALL, MIDDLE) + stiff_round(WALL_WIDE, MIDDLE_BACK_HALF_OPEN)
                 + third_round(BACK_BAND_MIDDLE + BACK_BAND_LOW + BACK_BAND_HIGH + AGAINST_C4)),
    "expert_5": ("three rounds, the second's low wall bites with the jaws opened only 0.6, the "
                 "third starting against C4", 0.6,
                 stiff_round(WALL, MIDDLE) + stiff_round(WALL_WIDE_LOW_HALF_OPEN, MIDDLE)
                 + third_round(AGAINST_C4 + BACK_BAND_HIGH + BACK_BAND_MIDDLE + BACK_BAND_LOW)),
}


def novices(reference, time_limit_s, slow_pace=2.0):
    """The same five kinds of error for every anatomical module (the hesitant one at slow_pace,
    slower than the module's experts)."""
    # Too slow: the reference plan at the pace 2.0 with a pause before each scoop; the time limit
    # runs out after a few scoops.
    slow = []
    for s in reference:
        slow.append(PAUSE(6.0, "hesitates over the window"))
        slow.append(s)
    return {
        "novice_drift": ("three clean scoops, then the cup wanders out of the window to the "
                         "left, past the edge of the vertebral body and down beside the uncinate "
                         "process to 0.5 mm from the left vertebral artery's zone", 0.75,
                         [F1, F2, M1, DRIFT()]),
        "novice_plunge": ("one clean scoop, then a plunge through the posterior annulus, the "
                          "cup's back 1.5 mm into the spinal cord / PLL zone", 0.75,
                          [F1, PLUNGE()]),
        "novice_lever": ("one clean scoop, then levering on the shaft (roll 24 deg each way) "
                         "with the cup deep in the disc: the shaft bears on the endplate rims",
                         0.75, [F1, LEVER()]),
        "novice_scrape": ("one clean scoop, then the cup pressed down through the cartilage "
                          "into the C5 endplate with %g N and scraped along and across its "
                          "middle" % SCRAPE_FORCE_N, 0.75, [F1, SCRAPE()]),
        "novice_slow": ("hesitation: the reference plan at pace %g, pausing 6 s over the "
                        "window before each scoop; the time limit (%g s) ends it"
                        % (slow_pace, time_limit_s), slow_pace, slow),
    }


def plans_for(module_path, g):
    experts = EXPERTS_90 if g["time_limit_s"] and g["time_limit_s"] < 100 else EXPERTS_120
    # 1.6 removed 25 % of 02's nucleus by the time limit once the nucleus's contacts only
    # pushed, at or above three quarters of the experts' mean: the hesitant novice passed.
    slow_pace = 2.0
    if g["nucleus_viscosity_Pa_s"] > VISCOUS_PA_S:
        experts = EXPERTS_VISCOUS
        slow_pace = 2.4  # the experts there work at 1.45-1.55
    if {"rongeur", "angled"} <= set(g["roles"]):
        experts = EXPERTS_VISCOUS_TRAY if g["nucleus_viscosity_Pa_s"] > VISCOUS_PA_S else EXPERTS_TRAY
    plans = dict(experts)
    plans.update(novices(REFERENCE, g["time_limit_s"], slow_pace))
    return plans


def parse_moves(text):
    """Moves written on the command line (--moves), comma-separated: the names of this file's
    scoops (F1, M2, L1, ...), REFERENCE for the reference plan's fourteen, S:u0:u1:y:v for a
    scoop, P:u:y:v[:pitch] for a pull and R:u:y:v[:opening] for a rongeur's bite (the arguments
    of S, P and R) and A:u:y:v:axis[:opening] for an angled rongeur's bite."""
    named = {k: v for k, v in globals().items()
             if isinstance(v, tuple) and v and v[0] == "scoop"}
    moves = []
    for item in (t.strip() for t in text.split(",")):
        if not item:
            continue
        if item == "REFERENCE":
            moves.extend(REFERENCE)
        elif item in named:
            moves.append(named[item])
        elif item[:2] in ("S:", "P:", "R:", "A:"):
            try:
                args = [float(a) for a in item[2:].split(":")]
            except ValueError:
                args = []
            count = {"S": (4,), "P": (3, 4), "R": (3, 4), "A": (4, 5)}[item[0]]
            if len(args) not in count:
                raise ValueError("--moves: '%s': expected %s numbers after '%s:'"
                                 % (item, " or ".join(map(str, count)), item[0]))
            moves.append({"S": S, "P": P, "R": R, "A": A}[item[0]](item, *args))
        else:
            raise ValueError("--moves: '%s': expected a scoop's name (%s), REFERENCE, S:u0:u1:y:v, "
                             "P:u:y:v[:pitch], R:u:y:v[:opening] (a rongeur's bite) or "
                             "A:u:y:v:axis[:opening] (an angled rongeur's bite)"
                             % (item, ", ".join(sorted(named))))
    return moves


def fmt(t, cup, rpy, what):
    """A row; rpy may carry a fourth value, the grip (a rongeur's jaws, 0 open .. 1 closed)."""
    return "%.2f, %5.2f, %5.2f, %5.2f, %s   # %s" % (t, cup[0], cup[1], cup[2],
                                                   ", ".join("%g" % a for a in rpy), what)


def cup_rows(plan, g):
    """The cup-centre rows (strings, with '#' comments) of one plan on geometry g."""
    description, pace, moves = plan
    p = Placement(g)
    wipe_pitch, press = (80, 0.70) if g["angled"] else (65, 0.0)
    turn = 7.06 if g["angled"] else 8.0        # heights above the floor: turn, lift
    lift = 7.06 if g["angled"] else 6.0
    window, out_of_disc, clear = p.above(4.0), p.above(6.0), p.above(12.0)
    out = []
    t = 0.0
    last = (p.lateral(0.0, 0.0), 0.0, clear)
    out.append(fmt(t, last, (0, 0, 0, 1.0) if g["jaw"] else (0, 0, 0), "start, above the field"))
    n = 0

    def row(dt, cup, rpy, what):
        nonlocal t
        t += dt
        if g["jaw"] and len(rpy) == 3:
            rpy = tuple(rpy) + (1.0,)  # a rongeur's jaws stay closed unless a move opens them
        out.append(fmt(t, cup, rpy, what))

    limit = g["time_limit_s"]
    for m in moves:
        if limit and t >= limit:
            break  # the attempt ends at the time limit: no more moves
        if m[0] == "pause":
            row(m[2], last, (0, 0, 0), m[1])
            continue
        n += 1
        b = [x * pace for x in SCOOP_S]
        w = [x * pace for x in WIPE_S]
        if m[0] == "scoop":
            _, what, u0, u1, y, v = m
            yaw = 0 if u1 > u0 else 180
            z = p.depth(v)
            y = p.height(y)
            # the plunge passes through the window with 0.1 mm to spare each side
            x0 = max(-p.window, min(p.window, p.lateral(u0, z)))
            x1 = p.lateral(u1, z)
            out.append("# scoop %d: %s" % (n, what))
            row(b[0], (x0, y, window), (0, 0, yaw), "above the window")
            z0 = max(z, p.floor(x0))
            if z0 < p.ease_from:
                # deep: plunge to the middle, then ease back, so the gel ahead of the cup is not
                # driven into the posterior annulus (a fast plunge bulged it 0.7 mm backward)
                row(b[1], (x0, y, p.ease_from), (0, 0, yaw), "plunge into the nucleus")
                row(EASE_S * pace, (x0, y, z0), (0, 0, yaw), "ease back to the depth")
            else:
                row(b[1], (x0, y, z0), (0, 0, yaw), "plunge into the nucleus")
            # the sweep; where the posterior annulus curves forward, the cup follows it
            steps = 1 if max(p.floor(x0), p.floor(x1)) <= z else 4
            for k in range(1, steps + 1):
                xk = x0 + (x1 - x0) * k / steps
                row(b[2] / steps, (xk, y, max(z, p.floor(xk))), (0, 0, yaw),
                    "sweep toward the opening: the cup fills" if k == steps else
                    "sweep, clear of the posterior annulus")
            row(b[3], (x1, y, out_of_disc), (0, 0, yaw), "straight withdrawal")
            row(b[4], (x1, 0.0, clear), (0, 0, yaw), "")
        elif m[0] in ("bite", "angled_bite"):
            (bite_rows if m[0] == "bite" else angled_bite_rows)(m, g, p, row, out, n, pace)
            last = (p.lateral(0.0, 0.0), 0.0, clear)
            continue
        elif m[0] == "pull":
            _, what, u, y, v, pitch = m
            side = 1.0 if u >= 0 else -1.0
            # the opening toward the lane's side (and the surgeon, on the angled cup)
            yaw = 0 if side > 0 else 180
            rpy = (0, -pitch if g["angled"] else 0, yaw)
            y = p.height(y)
            z = p.depth(v)
            x0 = max(-p.window, min(p.window, p.lateral(u, z)))
            out.append("# pull %d: %s" % (n, what))
            row(b[0], (x0, y, window), rpy, "above the window")
            z0 = max(z, p.floor(x0))
            if z0 < p.ease_from:
                row(b[1], (x0, y, p.ease_from), rpy, "plunge, the cup's back first")
                row(EASE_S * pace, (x0, y, z0), rpy, "ease back to the depth")
            else:
                row(b[1], (x0, y, z0), rpy, "plunge, the cup's back first")
            x1 = p.lateral(u, z0)
            zb = max(z0, p.floor(x1))
            row(b[2] * 0.5, (x1, y, zb), rpy, "out to the lane, along the back")
            # the pull: straight forward along the lane, the lane closing in to the window's
            # edge where the nucleus narrows toward its front
            steps = 4
            zf = g["nucleus_cz"] + g["nucleus_b"]
            for k in range(1, steps + 1):
                zk = zb + (zf - zb) * k / steps
                lim = max(p.reach(zk), p.window)
                xk = g["nucleus_cx"] + side * min(abs(x1 - g["nucleus_cx"]), lim)
                row(b[3] / steps, (xk, y, zk), rpy, "pull toward the surgeon" if k == 1 else "")
            xk = g["nucleus_cx"] + side * min(abs(x1 - g["nucleus_cx"]), p.window)
            row(b[2] * 0.5, (xk, y, out_of_disc), rpy, "on out through the window")
            row(b[4], (xk, 0.0, clear), (0, 0, yaw), "")
        else:
            kind, what, rows = m
            out.append("# %d: %s" % (n, what))
            cup = last
            for r in rows:
                if kind == "press_rows":
                    dt, (x, y, z), note = r
                    rpy = (0, 0, 0)
                else:
                    dt, (x, y, z), rpy, note = r
                if kind == "artery_rows":
                    cup = p.artery(x, y, z)
                else:
                    # u as a fraction of the nucleus's semi-axis, not kept inside it: these are
                    # the mistakes
                    xx = g["nucleus_cx"] + x * g["nucleus_a"]
                    if z is None:
                        zz = window
                    elif kind == "cord_rows":
                        zz = g["body_back_z"] + z
                    else:
                        zz = p.depth(z)
                    yy = 0.0 if y is None else y
                    if y == "press":
                        yy, rise, roll = p.press(SCRAPE_FORCE_N)
                        zz += rise
                        rpy = (round(roll, 1), 0, 0)
                    cup = (xx, yy, zz)
                row(dt * pace, cup, rpy, note)
            row(b[4], (cup[0], 0.0, clear), (0, 0, 0), "")
        # the wipe on the tray
        row(w[0], p.tray(4.0, 2.0, 14.0), (0, 0, 0), "over the tray")
        row(w[1], p.tray(4.0, 2.0, turn), (0, wipe_pitch, 0),
            "opening turned down (pitch %d)" % wipe_pitch)
        row(w[2], p.tray(4.0, 2.0, press), (0, wipe_pitch, 0),
            "lip pressed into the tray floor")
        row(w[3], p.tray(-6.0, 2.0, press), (0, wipe_pitch, 0), "wipe: drag 10 mm, lip first")
        row(w[4], p.tray(-6.0, 2.0, lift), (0, wipe_pitch, 0), "lift off")
        row(w[5], p.tray(0.0, g["tray_far_y"] - g["tray_cy"], 14.0), (0, 0, 0), "")
        last = (p.lateral(0.0, 0.0), 0.0, clear)
    return description, out


def bite_rows(m, g, p, row, out, n, pace):
    """The rows of one rongeur bite (R) and its release over the tray: the jaws' middle, the
    stylus's roll, pitch and yaw, and the grip (0 open .. 1 closed)."""
    _, what, u, y, v, opening = m
    jw = g["jaw"]
    half_thick = jw["depth"] + jw["wall"]     # closed jaws, from the axis
    half_len = 0.5 * jw["length"]
    y_max = 0.5 * g["disc_height"] - ENDPLATE_WARNING_MM - 0.5 * jw["width"] - 0.15
    y = max(-y_max, min(y_max, y))
    x = g["nucleus_cx"] + u * g["nucleus_a"]
    s = max(-1.0, min(1.0, (x - g["nucleus_cx"]) / g["nucleus_a"]))
    back_edge = g["nucleus_cz"] - g["nucleus_b"] * math.sqrt(max(0.0, 1.0 - s * s))
    z_tip = max(g["nucleus_cz"] + v * g["nucleus_b"], back_edge + TIP_CLEARANCE_MM,
                g["body_back_z"] + CORD_WARNING_MM + CORD_MARGIN_MM)
    # the closed jaws pass the window (the bodies' front) with 0.1 mm to spare each side; a lane
    # further out tilts the shaft about the window (pitch about y; negative leans the tips to +x)
    z_window = g["body_front_z"]
    x_pass = g["window_half"] - half_thick - 0.1
    pitch = 0.0
    if abs(x - g["nucleus_cx"]) > x_pass:
        side = 1.0 if x > g["nucleus_cx"] else -1.0
        lean = math.atan((abs(x - g["nucleus_cx"]) - x_pass) / max(1.0, z_window - z_tip))
        pitch = -side * math.degrees(lean)
    ph = math.radians(pitch)
    axis = (math.sin(ph), 0.0, math.cos(ph))  # body +z in the segment frame: tip -> grip

    def middle(tip):  # the jaws' middle for their tips at `tip`
        return (tip[0] + half_len * axis[0], tip[1], tip[2] + half_len * axis[2])

    # the opening, narrowed until the open tips stay within reach of the nucleus's edge
    full = 0.5 * math.radians(jw["opening_deg"])
    reach = p.reach(z_tip) + JAW_LATERAL_REACH_MM - abs(x - g["nucleus_cx"])
    o = max(0.0, min(1.0, opening))
    while o > 0.05:
        a = full * o
        if jw["length"] * math.sin(a) + half_thick * math.cos(a) <= reach:
            break
        o -= 0.05
    open_grip = round(1.0 - o, 2)
    b = carried([d * pace for d in BITE_S], BITE_S, (6, 7))
    rpy = (0, round(pitch, 2), 0)
    tip_window = (x - (z_window + 4.0 - z_tip) * axis[0], y, z_window + 4.0)
    out.append("# bite %d: %s (jaws opened to closure %.2f%s)"
               % (n, what, open_grip, ", shaft tilted %.1f deg" % pitch if pitch else ""))
    row(b[0], middle(tip_window), rpy + (1.0,), "over the window, jaws closed")
    tip = (x, y, z_tip)
    row(b[1], middle(tip), rpy + (1.0,), "in through the window to the target")
    row(b[2], middle(tip), rpy + (open_grip,), "open the jaws")
    row(b[3], middle(tip), rpy + (open_grip,), "")
    row(b[4], middle(tip), rpy + (1.0,), "bite: close the jaws")
    row(b[5], middle(tip), rpy + (1.0,), "")
    tip_out = (x - (z_window + 6.0 - z_tip) * axis[0], y, z_window + 6.0)
    row(b[6], middle(tip_out), rpy + (1.0,), "straight out, jaws closed on the bite")
    clear = p.above(12.0)
    row(b[7], (tip_out[0], 0.0, clear + half_len), (0, 0, 0, 1.0), "")
    release_rows(g, p, row, n, pace, half_len)


# The pace of the releases over the tray, if not the plan's (--release-pace): the stiff gel of
# module 03 wants slow bites, but the way to the tray and back is in the air.
RELEASE_PACE = None
# The pace of the rows that carry a bite (out of the disc, up, over the tray and down to it), if
# not the plan's (--carry-pace): a held bite of module 03's stiff gel carried to the tray at the
# plan's pace overloaded the shaft (docs/anatomy.md).
CARRY_PACE = None


def carried(b, base, rows):
    """b with the rows that carry a bite (their indices in base) at CARRY_PACE, if it is set."""
    if CARRY_PACE is not None:
        for k in rows:
            b[k] = base[k] * CARRY_PACE
    return b


def release_rows(g, p, row, n, pace, half_len, tip_mm=RELEASE_TIP_MM):
    """Over the tray: the tips tip_mm above its floor (what hangs from them touches it), open,
    wait, up, close; each bite in a lane of its own across the tray."""
    w = carried([d * (pace if RELEASE_PACE is None else RELEASE_PACE) for d in RELEASE_S],
                RELEASE_S, (0, 1))
    lane = ((n * 3) % 19) - 9.0
    tray_hi = p.tray(lane, 0.0, 14.0 + half_len)
    tray_lo = p.tray(lane, 0.0, tip_mm + half_len)
    row(w[0], tray_hi, (0, 0, 0, 1.0), "over the tray")
    row(w[1], tray_lo, (0, 0, 0, 1.0), "down")
    row(w[2], tray_lo, (0, 0, 0, 0.0), "open: the bite drops")
    row(w[3], tray_lo, (0, 0, 0, 0.0), "")
    row(w[4], tray_hi, (0, 0, 0, 0.0), "up, jaws open")
    row(w[5], tray_hi, (0, 0, 0, 1.0), "close")


def angled_bite_rows(m, g, p, row, out, n, pace):
    """The rows of one angled bite (A) and its release over the tray: the jaws' middle, the
    stylus's roll, pitch and yaw, and the grip (0 open .. 1 closed)."""
    _, what, u, y, v, axis_deg, opening = m
    jw = g["jaw"]
    if jw is None:
        raise ValueError("--moves: '%s': an angled bite needs a rongeur (the module's instrument "
                         "is not one)" % what)
    half_len = 0.5 * jw["length"]
    y_max = 0.5 * g["disc_height"] - ENDPLATE_WARNING_MM - 0.5 * jw["width"] - 0.15
    y = max(-y_max, min(y_max, y))
    # The roll that leans the bend the axis's way, and the shaft's lean (deg from -z toward +x)
    # the bend leaves: yaw 0 turns the instrument's +x to the segment's +x, yaw 180 to -x, and
    # with yaw 180 a pitch leans the shaft's tip the other way (c4c5_waypoints.rotation).
    side = 1.0 if axis_deg >= 0 else -1.0
    lean = axis_deg - side * jw["angle_deg"]
    yaw = 0 if side > 0 else 180
    rpy = (0, round(-lean if side > 0 else lean, 2), yaw)
    phi, psi = math.radians(axis_deg), math.radians(lean)
    axis = (math.sin(phi), -math.cos(phi))      # (x, z) along the jaws into the disc
    shaft = (-math.sin(psi), math.cos(psi))     # (x, z) up the shaft, toward the grip
    mid = [g["nucleus_cx"] + u * g["nucleus_a"], g["nucleus_cz"] + v * g["nucleus_b"]]
    o = max(0.0, min(1.0, opening))
    a_open = 0.5 * math.radians(jw["opening_deg"]) * o
    # The open jaws' tips (the middle of each plate's end) stay ANGLED_TIP_CLEARANCE_MM in front of
    # the nucleus's posterior edge where they are over its back (within 0.9 of its half-width
    # of the middle), and out of the cord zone's band: the middle is drawn back along the shaft
    # until they do. The posterior annulus has the canal behind it and 0.35 mm to the removal
    # region's back (Placement.floor); a tip further out bears on the lateral annulus, which
    # has the ring's width to give (angled bites along the side, measured on module 02).
    half_thick = jw["depth"] + 0.5 * jw["wall"]
    for _ in range(2):
        hinge = (mid[0] - half_len * axis[0], mid[1] - half_len * axis[1])
        deficit = 0.0
        for k in (-1, 1):
            t = phi + k * a_open
            tip = (hinge[0] + jw["length"] * math.sin(t) + k * half_thick * math.cos(t),
                   hinge[1] - jw["length"] * math.cos(t) + k * half_thick * math.sin(t))
            s_ = (tip[0] - g["nucleus_cx"]) / g["nucleus_a"]
            floor = g["body_back_z"] + CORD_WARNING_MM + CORD_MARGIN_MM
            if abs(s_) < ANGLED_BACK_SPAN:
                floor = max(floor, g["nucleus_cz"] - g["nucleus_b"] * math.sqrt(1.0 - s_ * s_)
                            + ANGLED_TIP_CLEARANCE_MM)
            deficit = max(deficit, floor - tip[1])
        if deficit <= 0.0:
            break
        mid = [mid[0] + deficit / shaft[1] * shaft[0], mid[1] + deficit]
    hinge = (mid[0] - half_len * axis[0], mid[1] - half_len * axis[1])
    # The shaft passes the window (the bodies' front) with 0.1 mm to spare.
    z_window = g["body_front_z"]
    x_window = hinge[0] + (z_window - hinge[1]) / shaft[1] * shaft[0]
    limit = g["window_half"] - g["shaft_r"] - 0.1
    if abs(x_window - g["nucleus_cx"]) > limit:
        raise ValueError("--moves: '%s': the shaft would cross the window at x = %.2f mm, beyond "
                         "the %.2f mm it passes (lean %.1f deg); move the bite or its axis"
                         % (what, x_window, limit, lean))
    # Opened, the jaws' lowest tip below their middle; the middle drawn back along the shaft
    # until that tip is 4 mm above the window (before the plunge) or the closed tips 6 mm
    # above it (after the bite).
    low_open = min(hinge[1] - jw["length"] * math.cos(phi + k * a_open) for k in (-1, 1)) - mid[1]
    low_closed = hinge[1] - jw["length"] * math.cos(phi) - mid[1]

    def drawn_back(low, above):
        d = (z_window + above - low - mid[1]) / shaft[1]
        return (mid[0] + d * shaft[0], y, mid[1] + d * shaft[1])

    open_grip = round(1.0 - o, 2)
    b = carried([d * pace for d in BITE_S], BITE_S, (6, 7))
    out.append("# angled bite %d: %s (jaws' axis %.1f deg, shaft leaning %.1f deg, yaw %d, "
               "jaws opened to closure %.2f)" % (n, what, axis_deg, lean, yaw, open_grip))
    above = drawn_back(low_open, 4.0)
    target = (mid[0], y, mid[1])
    row(b[0], above, rpy + (1.0,), "over the window, jaws closed")
    row(b[2], above, rpy + (open_grip,), "open the jaws above the window")
    row(b[1], target, rpy + (open_grip,), "in along the shaft, the jaws open")
    row(b[3], target, rpy + (open_grip,), "")
    row(b[4], target, rpy + (1.0,), "bite: close the jaws")
    row(b[5], target, rpy + (1.0,), "")
    out_of_disc = drawn_back(low_closed, 6.0)
    row(b[6], out_of_disc, rpy + (1.0,), "out along the shaft, jaws closed on the bite")
    clear = p.above(12.0)
    row(b[7], (out_of_disc[0], 0.0, clear + half_len), (0, 0, 0, 1.0), "")
    # upright over the tray, the angled jaws' tips lie L/2 cos(bend) below their middle
    release_rows(g, p, row, n, pace, half_len * math.cos(math.radians(jw["angle_deg"])),
                 ANGLED_RELEASE_TIP_MM)


def header(name, description, g, module_path):
    return [
        "# %s for %s: %s." % (name, os.path.basename(module_path), description),
        "# Written by content/demonstrations/scoop_plans.py from the module's disc, window, curette",
        "# and tray; do not edit by hand (scripts/demonstrations regenerates it).",
        "# Cup-centre rows for c4c5_waypoints.py: t_s, cup x, y, z (mm), roll, pitch, yaw (deg).",
    ]


@contextlib.contextmanager
def part_settings(release_tip_mm=None, release_pace=None, carry_pace=None):
    """The generator's release and carry options (the command line's --release-tip-mm,
    --release-pace, --carry-pace) set for one part of a plan, and put back after it."""
    global ANGLED_RELEASE_TIP_MM, RELEASE_PACE, CARRY_PACE
    saved = ANGLED_RELEASE_TIP_MM, RELEASE_PACE, CARRY_PACE
    if release_tip_mm is not None:
        ANGLED_RELEASE_TIP_MM = release_tip_mm
    if release_pace is not None:
        RELEASE_PACE = release_pace
    if carry_pace is not None:
        CARRY_PACE = carry_pace
    try:
        yield
    finally:
        ANGLED_RELEASE_TIP_MM, RELEASE_PACE, CARRY_PACE = saved


def is_tray_plan(plan):
    """A plan of parts (EXPERTS_TRAY) rather than of one instrument's moves."""
    moves = plan[2]
    return bool(moves) and isinstance(moves[0], tuple) and moves[0][0] in ("cup", "rongeur",
                                                                           "angled")


def plan_files(name, plan, module, module_path, instrument=0):
    """The lines of a plan's .cup.csv and .waypoints.csv. A tray plan's parts are placed each
    for its own instrument and joined, the instrument exchanged between them; its .cup.csv
    lists each part's rows after a '# part' line, each part's time from 0."""
    g0 = module_geometry(module, instrument)
    if not is_tray_plan(plan):
        description, rows = cup_rows(plan, g0)
        lines = header(name, description, g0, module_path) + rows
        return lines, c4c5_waypoints.waypoint_lines(lines, g0["grip_mm"], g0["grip_lateral_mm"])
    description, pace, parts = plan
    cup, joined = header(name, description, g0, module_path), []
    for k, part in enumerate(parts):
        role, moves = part[0], part[1]
        if role not in g0["roles"]:
            raise ValueError("%s: the module's tray has no %s" % (name, role))
        index = g0["roles"][role]
        g = module_geometry(module, index)
        with part_settings(**(part[2] if len(part) > 2 else {})):
            _, rows = cup_rows((description, pace, moves), g)
        cup.append("# part %d: the %s (instrument %d)" % (k + 1, role, index))
        cup.extend(rows)
        joined.append(("%s part %d, the %s" % (name, k + 1, role),
                       c4c5_waypoints.waypoint_lines(rows, g["grip_mm"], g["grip_lateral_mm"]),
                       index))
    waypoints = [line for line in cup if line.startswith("#") and not line.startswith("# part")
                 and not line.startswith("# Cup-centre")]
    lines = join_waypoints.join_parts(joined, PART_GAP_S)
    return cup, lines[:1] + waypoints + lines[1:]


def main():
    ap = argparse.ArgumentParser(description="cup-centre plans of the C4-C5 demonstrations")
    ap.add_argument("module", help="module file (scenarios/modules/0[2-4]_*.json)")
    ap.add_argument("plan", nargs="?", help="one plan name (expert_N, novice_KIND)")
    ap.add_argument("--list", action="store_true", help="list the plans for this module")
    ap.add_argument("--write-dir", help="write every plan's .cup.csv and .waypoints.csv here")
    ap.add_argument("--moves", help="a plan of these moves instead of the bundled ones (named "
                    "PLAN, default 'trial'): e.g. 'F1,F2,P:0.75:0.6:-0.6' (parse_moves)")
    ap.add_argument("--pace", type=float, default=0.65, help="the --moves plan's pace (0.65)")
    ap.add_argument("--instrument", type=int, default=0, help="the --moves plan's instrument: "
                    "its place on the module's tray (world.instruments), 0 the first")
    ap.add_argument("--release-tip-mm", type=float, default=None,
                    help="an angled bite's tips above the tray's floor where the jaws let the "
                    "bite go (%g)" % ANGLED_RELEASE_TIP_MM)
    ap.add_argument("--release-pace", type=float, default=None,
                    help="the pace of the bites' releases over the tray (the plan's pace)")
    ap.add_argument("--carry-pace", type=float, default=None,
                    help="the pace at which a bite is carried out of the disc and down to the "
                    "tray (the plan's, or the releases' there)")
    args = ap.parse_args()
    with open(args.module) as f:
        module = json.load(f)
    instrument = args.instrument if args.moves is not None else 0
    try:
        g = module_geometry(module, instrument)
    except ValueError as e:
        sys.stderr.write("%s\n" % e)
        return 2
    plans = plans_for(args.module, g)
    if args.moves is not None:
        try:
            moves = parse_moves(args.moves)
        except ValueError as e:
            sys.stderr.write("%s\n" % e)
            return 2
        args.plan = args.plan or "trial"
        plans = {args.plan: ("the moves %s at pace %g" % (args.moves, args.pace), args.pace,
                             moves)}
    if args.list:
        for name, plan in plans.items():
            print("%-14s %s" % (name, plan[0]))
        return 0
    names = list(plans) if args.write_dir else [args.plan]
    if not args.write_dir and args.plan not in plans:
        sys.stderr.write("%s: no plan '%s' (expected one of %s)\n"
                         % (args.module, args.plan, ", ".join(plans)))
        return 2
    for name in names:
        try:
            with part_settings(args.release_tip_mm, args.release_pace, args.carry_pace):
                cup, waypoints = plan_files(name, plans[name], module, args.module, instrument)
        except ValueError as e:  # a move the anatomy does not allow (an angled bite's shaft)
            sys.stderr.write("%s\n" % e)
            return 2
        if not args.write_dir:
            print("\n".join(cup))
            return 0
        with open(os.path.join(args.write_dir, name + ".cup.csv"), "w") as f:
            f.write("\n".join(cup) + "\n")
        with open(os.path.join(args.write_dir, name + ".waypoints.csv"), "w") as f:
            f.write("\n".join(waypoints) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
