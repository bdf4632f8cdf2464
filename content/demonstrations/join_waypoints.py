#!/usr/bin/env python3
"""Joins grip waypoint files into one attempt that exchanges instruments between them.

Each part is a waypoint file (`scoop_plans.py ... --write-dir`, grip poses in millimetres and
degrees) and the place of its instrument on the scene's tray (`world.instruments`, 0 the
first). The parts follow one another, each shifted to start `--gap` seconds after the last row
of the one before (the hand's move from where that part ended to where the next begins); every
row gets the grip column (1, closed, for a part without one: only a rongeur reads it) and the
instrument column, so the simulation takes the next part's instrument as soon as the one in
hand is out of the disc (docs/scenario-format.md, "Exchanging instruments"). A part's rows are
placed for its own instrument: write a rongeur's bites on a copy of the module whose
instrument is the rongeur, and a curette's scoops on the module itself.

    python3 join_waypoints.py OUT.waypoints.csv bites.waypoints.csv:1 scoops.waypoints.csv:0
    acdr make-trajectory OUT.waypoints.csv OUT.csv
"""
import argparse
import sys


def parse_rows(lines, source):
    """(header columns, rows as lists of floats) of a waypoint file's lines; comments dropped.
    `source` names the lines in errors."""
    header, rows = None, []
    for n, line in enumerate(lines, 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        if header is None:
            header = line.replace(" ", "").split(",")
            if header[:7] != ["t_s", "x_mm", "y_mm", "z_mm", "roll_deg", "pitch_deg", "yaw_deg"]:
                raise ValueError("%s:%d: not a waypoint header (got '%s')" % (source, n, line))
            if "instrument" in header:
                raise ValueError("%s:%d: already has an instrument column" % (source, n))
            continue
        values = [float(v) for v in line.split(",")]
        if len(values) != len(header):
            raise ValueError("%s:%d: expected %d values, got %d"
                             % (source, n, len(header), len(values)))
        rows.append(values)
    if not rows:
        raise ValueError("%s: no waypoints" % source)
    return header, rows


def join_parts(parts, gap_s):
    """The joined waypoint lines of [(name, waypoint lines, instrument index)]."""
    out = ["t_s,x_mm,y_mm,z_mm,roll_deg,pitch_deg,yaw_deg,grip,instrument"]
    offset = 0.0
    for k, (name, lines, instrument) in enumerate(parts):
        header, rows = parse_rows(lines, name)
        has_grip = "grip" in header
        out.append("# part %d: %s, instrument %d" % (k + 1, name, instrument))
        shift = offset - rows[0][0] + (gap_s if k > 0 else 0.0)
        for v in rows:
            grip = v[7] if has_grip else 1.0
            out.append("%.3f,%.3f,%.3f,%.3f,%.2f,%.2f,%.2f,%.3f,%d"
                       % (v[0] + shift, v[1], v[2], v[3], v[4], v[5], v[6], grip, instrument))
        offset = rows[-1][0] + shift
    return out


def join(parts, gap_s):
    """The joined waypoint lines of [(path, instrument index)]."""
    files = []
    for path, instrument in parts:
        with open(path) as f:
            files.append((path, f.read().splitlines(), instrument))
    return join_parts(files, gap_s)


def main():
    ap = argparse.ArgumentParser(description="join waypoint files, exchanging instruments")
    ap.add_argument("out", help="the joined waypoint file to write")
    ap.add_argument("parts", nargs="+", help="FILE:INSTRUMENT, in order (INSTRUMENT: the place "
                    "on the scene's tray, 0 the first)")
    ap.add_argument("--gap", type=float, default=1.0,
                    help="seconds from one part's last row to the next part's first (1.0)")
    args = ap.parse_args()
    parts = []
    for p in args.parts:
        path, sep, index = p.rpartition(":")
        if not sep or not index.isdigit():
            sys.stderr.write("%s: expected FILE:INSTRUMENT with INSTRUMENT a whole number 0 or "
                             "more\n" % p)
            return 2
        parts.append((path, int(index)))
    if not args.gap > 0.0:
        sys.stderr.write("--gap: expected more than 0 s (got %g)\n" % args.gap)
        return 2
    try:
        lines = join(parts, args.gap)
    except (OSError, ValueError) as e:
        sys.stderr.write("%s\n" % e)
        return 2
    with open(args.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
