"""Write part.dxf of this example with ezdxf (run from this folder: python make_dxf.py).

A 120 x 80 mm plate (millimetres, $INSUNITS = 4) with 6 mm corner radii (LINEs and
ARCs, layer OUTLINE); four 6.6 mm and two 10 mm holes (CIRCLEs, layer HOLES); a 19 mm
bore (layer BORE); three slots 8 mm wide, 16 mm between centres (two LINEs and two
ARCs each), and an oval (an ELLIPSE 10 x 16), layer SLOTS.
"""

from pathlib import Path

import ezdxf


def make(path: Path) -> Path:
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    a = {"layer": "OUTLINE"}
    r = 6.0
    for p, q in (((r, 0), (120 - r, 0)), ((120, r), (120, 80 - r)),
                 ((120 - r, 80), (r, 80)), ((0, 80 - r), (0, r))):
        msp.add_line(p, q, dxfattribs=a)
    for c, a0 in (((120 - r, r), -90), ((120 - r, 80 - r), 0), ((r, 80 - r), 90), ((r, r), 180)):
        msp.add_arc(c, r, a0, a0 + 90, dxfattribs=a)
    for c in ((10, 10), (110, 10), (10, 70), (110, 70)):
        msp.add_circle(c, 3.3, dxfattribs={"layer": "HOLES"})
    for c in ((35, 62), (85, 62)):
        msp.add_circle(c, 5.0, dxfattribs={"layer": "HOLES"})
    msp.add_circle((60, 40), 9.5, dxfattribs={"layer": "BORE"})
    s = {"layer": "SLOTS"}
    for (x0, y0), (x1, y1) in (((30, 18), (46, 18)), ((74, 18), (90, 18))):
        msp.add_line((x0, y0 - 4), (x1, y1 - 4), dxfattribs=s)
        msp.add_arc((x1, y1), 4, -90, 90, dxfattribs=s)
        msp.add_line((x1, y1 + 4), (x0, y0 + 4), dxfattribs=s)
        msp.add_arc((x0, y0), 4, 90, 270, dxfattribs=s)
    msp.add_line((104, 34), (104, 50), dxfattribs=s)          # vertical slot at x = 100
    msp.add_arc((100, 50), 4, 0, 180, dxfattribs=s)
    msp.add_line((96, 50), (96, 34), dxfattribs=s)
    msp.add_arc((100, 34), 4, 180, 360, dxfattribs=s)
    msp.add_ellipse((22, 42), (0, 8), 5 / 8, dxfattribs=s)
    doc.saveas(path)
    return path


if __name__ == "__main__":
    make(Path(__file__).with_name("part.dxf"))
