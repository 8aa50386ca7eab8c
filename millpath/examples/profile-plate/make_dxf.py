"""Write part.dxf of this example with ezdxf (run from this folder: python make_dxf.py).

A 100 x 60 mm plate (millimetres, $INSUNITS = 4) with 8 mm corner radii drawn as one
LWPOLYLINE with bulges (layer OUTLINE), four 9 mm bolt holes (M8 clearance) and a 20 mm bore
(CIRCLE, layer HOLES) and a slot 8 mm wide with 24 mm between its centres drawn as two
LINEs and two ARCs (layer SLOTS).
"""

from pathlib import Path

import ezdxf

B = 0.41421356237309503          # bulge of a quarter circle: tan(90 deg / 4)


def make(path: Path) -> Path:
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    r = 8.0
    # counter-clockwise outline with rounded corners: (x, y, bulge)
    msp.add_lwpolyline([(r, 0, 0), (100 - r, 0, B), (100, r, 0), (100, 60 - r, B),
                        (100 - r, 60, 0), (r, 60, B), (0, 60 - r, 0), (0, r, B)],
                       format="xyb", close=True, dxfattribs={"layer": "OUTLINE"})
    for x, y in [(10, 10), (90, 10), (10, 50), (90, 50)]:
        msp.add_circle((x, y), 4.5, dxfattribs={"layer": "HOLES"})
    msp.add_circle((30, 30), 10.0, dxfattribs={"layer": "HOLES"})
    a = {"layer": "SLOTS"}
    msp.add_line((58, 26), (82, 26), dxfattribs=a)
    msp.add_arc((82, 30), 4, -90, 90, dxfattribs=a)
    msp.add_line((82, 34), (58, 34), dxfattribs=a)
    msp.add_arc((58, 30), 4, 90, 270, dxfattribs=a)
    doc.saveas(path)
    return path


if __name__ == "__main__":
    make(Path(__file__).with_name("part.dxf"))
