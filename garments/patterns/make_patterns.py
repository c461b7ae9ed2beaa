#!/usr/bin/env python3
"""Writes tryon's shipped sewing patterns (size M, centimetres) in the GarmentCode JSON layout.

Run from this folder: python3 make_patterns.py. The JSON files are committed; this script is
how they were drawn. Panels are drawn as seen from the front of the body (x = world x, the
body's left at +x); back panels are mirrored into their own frame, which faces -z (rotation
180 degrees about y), so every outline runs counter-clockwise seen from outside the body.
The file placement is for tryon's average body (bodyfit's default shape) standing at the
origin; garments/place.c re-places panels around any body.
"""
import json
import math


def rel(s, e, p):
    """Absolute control point p to GarmentCode's relative (cx, cy)."""
    dx, dy = e[0] - s[0], e[1] - s[1]
    qx, qy = p[0] - s[0], p[1] - s[1]
    l2 = dx * dx + dy * dy
    return [round((qx * dx + qy * dy) / l2, 5), round((qy * dx - qx * dy) / l2, 5)]


class Panel:
    """pts: outline corners; edges[i] = (name, curve) from pts[i] to pts[i+1]; curve None, an
    absolute quadratic control point ("q", (x, y)) or a circle ("c", radius, large, right)."""

    def __init__(self, pts, edges):
        self.pts = [tuple(p) for p in pts]
        self.edges = list(edges)

    def mirrored(self):
        n = len(self.pts)
        pts = [(-x, y) for x, y in reversed(self.pts)]
        edges = []
        for i in range(n):  # new edge i runs from old vertex n-1-i to n-2-i
            name, curve = self.edges[n - 2 - i]
            if curve and curve[0] == "q":
                curve = ("q", (-curve[1][0], curve[1][1]))
            edges.append((name, curve))
        return Panel(pts, edges)

    def area(self):
        a = 0
        for i in range(len(self.pts)):
            x0, y0 = self.pts[i]
            x1, y1 = self.pts[(i + 1) % len(self.pts)]
            a += x0 * y1 - x1 * y0
        return a / 2

    def spec(self, translation, rotation):
        assert self.area() > 0, "outline must run counter-clockwise"
        n = len(self.pts)
        edges = []
        for i, (name, curve) in enumerate(self.edges):
            e = {"endpoints": [i, (i + 1) % n], "label": name}
            s, t = self.pts[i], self.pts[(i + 1) % n]
            if curve and curve[0] == "q":
                e["curvature"] = {"type": "quadratic", "params": [rel(s, t, curve[1])]}
            elif curve:
                e["curvature"] = {"type": "circle", "params": list(curve[1:])}
            edges.append(e)
        return {"vertices": [list(p) for p in self.pts], "edges": edges,
                "translation": list(translation), "rotation": list(rotation)}

    def edge(self, name):
        return [e[0] for e in self.edges].index(name)


FRONT = (0, 0, 0)
BACK = (0, 180, 0)


def world(panel, t, r, p):
    """File placement of a panel point (rotations about y only are used here)."""
    a = math.radians(r[1])
    return (math.cos(a) * p[0] + t[0], p[1] + t[1])


def check_direction(panels, a, b):
    """The two sides of a seam run in opposite directions: a's start meets b's end."""
    (pa, ea), (pb, eb) = a, b
    ends = []
    for pn, en in ((pa, ea), (pb, eb)):
        panel, t, r = panels[pn]
        i = panel.edge(en)
        ends.append([world(panel, t, r, panel.pts[i]),
                     world(panel, t, r, panel.pts[(i + 1) % len(panel.pts)])])
    d = lambda p, q: math.hypot(p[0] - q[0], p[1] - q[1])
    same = d(ends[0][0], ends[1][0]) + d(ends[0][1], ends[1][1])
    opposite = d(ends[0][0], ends[1][1]) + d(ends[0][1], ends[1][0])
    assert opposite < same, "seam %s-%s runs the same way on both sides" % (a, b)


def write(name, panels, stitches):
    spec = {"pattern": {"panels": {}, "stitches": [], "panel_order": []},
            "properties": {"curvature_coords": "relative", "units_in_meter": 100,
                           "normalize_panel_translation": False},
            "parameters": {}, "parameter_order": [],
            "tryon": {"garment": name, "size": "M", "reference_body": "bodyfit average"}}
    for pname, (panel, t, r) in panels.items():
        spec["pattern"]["panels"][pname] = panel.spec(t, r)
        spec["pattern"]["panel_order"].append(pname)
    for (pa, ea), (pb, eb) in stitches:
        if panels[pa][2][2] == 0 and panels[pb][2][2] == 0:  # sleeves are placed folded
            check_direction(panels, (pa, ea), (pb, eb))
        spec["pattern"]["stitches"].append([
            {"panel": pa, "edge": panels[pa][0].edge(ea)},
            {"panel": pb, "edge": panels[pb][0].edge(eb)}])
    with open(name + ".json", "w") as f:
        json.dump(spec, f, indent=1)
        f.write("\n")


def tshirt_body(neck):
    """T-shirt front or back as drawn from the front; neck: the neckline's control height."""
    return Panel([(-28.5, 30), (28.5, 30), (28.5, 71), (22.5, 92.5), (8, 96), (-8, 96),
                  (-22.5, 92.5), (-28.5, 71)],
                 [("hem", None), ("side_r0", None), ("arm_r", ("q", (23, 77.5))),
                  ("shoulder_r", None), ("neck", ("q", (0, neck))), ("shoulder_l", None),
                  ("arm_l", ("q", (-23, 77.5))), ("side_l0", None)])


def tshirt():
    front = tshirt_body(80)
    back = tshirt_body(92).mirrored()
    sleeve = Panel([(-17, 0), (17, 0), (20, 20), (0, 32), (-20, 20)],
                   [("cuff", None), ("under_r", None), ("cap_a", None), ("cap_b", None),
                    ("under_l", None)])
    panels = {"front": (front, (0, 57, 16), FRONT), "back": (back, (0, 57, -16), BACK),
              "sleeve_l": (sleeve, (48, 120, 0), (0, 0, 90)),
              "sleeve_r": (sleeve, (-48, 120, 0), (0, 0, -90))}
    st = [(("front", "side_r0"), ("back", "side_r0")), (("front", "side_l0"), ("back", "side_l0")),
          (("front", "shoulder_r"), ("back", "shoulder_r")),
          (("front", "shoulder_l"), ("back", "shoulder_l")),
          (("front", "arm_r"), ("sleeve_l", "cap_b")), (("back", "arm_r"), ("sleeve_l", "cap_a")),
          (("front", "arm_l"), ("sleeve_r", "cap_a")), (("back", "arm_l"), ("sleeve_r", "cap_b")),
          (("sleeve_l", "under_r"), ("sleeve_l", "under_l")),
          (("sleeve_r", "under_r"), ("sleeve_r", "under_l"))]
    write("tshirt", panels, st)


def dress():
    # Sleeveless: the armhole cut in to a 6 cm shoulder, clear of the deltoid (where a wider
    # shoulder's corner stretched 40 %), and down to 2 cm under the armpit. The neckline 1 cm
    # wider each side and 2 cm (front) and 3 cm (back) deeper than it was: the narrower one lay on
    # the neck's base stretched 5.4 % along its whole length (docs/garments.md, "Strain").
    front = Panel([(-32, 0), (32, 0), (26.5, 45), (24.5, 57), (28, 70), (15, 95),
                   (9, 96), (-9, 96), (-15, 95), (-28, 70), (-24.5, 57), (-26.5, 45)],
                  [("hem", ("c", 200, 0, 1)), ("side_r0", None), ("side_r1", None),
                   ("side_r2", None), ("arm_r", ("q", (17, 76))), ("shoulder_r", None),
                   ("neck", ("q", (0, 76))), ("shoulder_l", None), ("arm_l", ("q", (-17, 76))),
                   ("side_l2", None), ("side_l1", None), ("side_l0", None)])
    back = Panel(front.pts, front.edges[:6] + [("neck", ("q", (0, 89)))] + front.edges[7:])
    back = back.mirrored()
    panels = {"front": (front, (0, 57, 15), FRONT), "back": (back, (0, 57, -15), BACK)}
    st = []
    for k in range(3):
        st.append((("front", "side_r%d" % k), ("back", "side_r%d" % k)))
        st.append((("front", "side_l%d" % k), ("back", "side_l%d" % k)))
    st += [(("front", "shoulder_r"), ("back", "shoulder_r")),
           (("front", "shoulder_l"), ("back", "shoulder_l"))]
    write("dress", panels, st)


def skirt():
    # The waist at the average body's waist (1.095 m: fit_model_measure) and 93 cm round: its
    # girth there is 85 cm (87 cm convex), plus 2 cm for the 3 mm the cloth is kept out, and the
    # S, graded 4 % smaller, must clear it too (at 90 cm the S's waist lay on the body 3.5 %
    # longer than cut). The waistband is fastened at its height (garments/dress_tryon.c): a
    # loose waist no longer slides down to the hips.
    front = Panel([(-34, 0), (34, 0), (28, 45), (24.75, 59), (-24.75, 59), (-28, 45)],
                  [("hem", ("c", 150, 0, 1)), ("side_r0", None), ("side_r1", ("q", (27.6, 53))),
                   ("waist", ("c", 120, 0, 0)), ("side_l1", ("q", (-27.6, 53))),
                   ("side_l0", None)])
    # The back takes the seat's curvature in two darts, 3 cm at the waist and 11.5 cm long, 10.5 cm
    # from the centre, its waist 0.7 cm higher there; without them the cloth over the seat was
    # stretched 3.7 % (S) from top to bottom (docs/garments.md, "Strain"). Front and back meet at
    # the side 24.75 cm from the centre (the darts' 6 cm out of the back's waist), so their side
    # seams are cut the same length.
    back = Panel([(-34, 0), (34, 0), (28, 45), (24.75, 59), (12, 59.6), (10.5, 48), (9, 59.7),
                  (-9, 59.7), (-10.5, 48), (-12, 59.6), (-24.75, 59), (-28, 45)],
                 [("hem", ("c", 150, 0, 1)), ("side_r0", None), ("side_r1", ("q", (27.6, 53))),
                  ("waist", None), ("dart_ra", None), ("dart_rb", None), ("waist", None),
                  ("dart_la", None), ("dart_lb", None), ("waist", None),
                  ("side_l1", ("q", (-27.6, 53))), ("side_l0", None)]).mirrored()
    panels = {"front": (front, (0, 50.5, 14), FRONT), "back": (back, (0, 50.5, -14), BACK)}
    st = [(("front", "side_r%d" % k), ("back", "side_r%d" % k)) for k in range(2)]
    st += [(("front", "side_l%d" % k), ("back", "side_l%d" % k)) for k in range(2)]
    st += [(("back", "dart_ra"), ("back", "dart_rb")), (("back", "dart_la"), ("back", "dart_lb"))]
    write("skirt", panels, st)


def jeans():
    # Drawn as seen from the front, the body's right leg (world -x); hem at y = 6 (ankle).
    # Crotch extensions 7.5 cm (front) and 12.5 cm (back) past the centre line: with 4.5 and 9 cm
    # the crotch seams hung 3 cm under the body stretched 4-6 % along their length (the thigh's
    # girth at the crotch wider than front and back together); 8 and 13.5 cm folded the L's
    # crotch through itself. The waist 97 cm (M), so that the S, graded 4 % smaller, still clears
    # the body's 86 cm waist by the 2 cm the cloth is kept out (docs/garments.md, "Strain").
    fr = Panel([(-16, 6), (-3, 6), (7.5, 73.5), (0, 84), (0, 104), (-23.25, 104), (-25.5, 84)],
               [("hem", None), ("inseam", None), ("crotch", ("q", (0.5, 74))), ("centre", None),
                ("waist", None), ("hip", ("q", (-24.5, 95))), ("side", None)])
    br_world = Panel([(-17.5, 6), (-2.5, 6), (12.5, 71), (2, 86), (3, 106), (-22.25, 104),
                      (-27.5, 84)],
                     [("hem", None), ("inseam", None), ("crotch", ("q", (2.5, 72.5))),
                      ("centre", None), ("waist", None), ("hip", ("q", (-25.5, 95))),
                      ("side", None)])
    br = br_world.mirrored()  # in its own frame, which faces -z
    fl, bl = fr.mirrored(), br_world
    panels = {"front_r": (fr, (0, 5, 12), FRONT), "front_l": (fl, (0, 5, 12), FRONT),
              "back_r": (br, (0, 5, -13), BACK), "back_l": (bl, (0, 5, -13), BACK)}
    st = []
    for side in "rl":
        st += [(("front_" + side, "side"), ("back_" + side, "side")),
               (("front_" + side, "hip"), ("back_" + side, "hip")),
               (("front_" + side, "inseam"), ("back_" + side, "inseam"))]
    for part in ("front", "back"):
        st += [((part + "_r", "crotch"), (part + "_l", "crotch")),
               ((part + "_r", "centre"), (part + "_l", "centre"))]
    write("jeans", panels, st)


if __name__ == "__main__":
    tshirt()
    dress()
    skirt()
    jeans()
