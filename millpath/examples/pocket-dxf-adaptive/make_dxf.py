"""Write part.dxf of this example with ezdxf (run from this folder: python make_dxf.py).

A 120 x 80 mm pocket (millimetres, $INSUNITS = 4) with sharp inner corners, a notch
18 mm wide on the top side, a half-round bulge on the right side (LWPOLYLINE bulge),
a round island (CIRCLE, diameter 24) and a slot-shaped island drawn as two LINEs and
two ARCs, all on layer POCKET. A layer NOTES holds a circle that is not part of it.
"""

from pathlib import Path

import ezdxf


def make(path: Path) -> Path:
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    a = {"layer": "POCKET"}
    # counter-clockwise outline: (x, y, bulge); bulge 1 on (120, 20) = half circle to (120, 60)
    msp.add_lwpolyline([(0, 0, 0), (120, 0, 0), (120, 20, 1), (120, 60, 0), (120, 80, 0),
                        (70, 80, 0), (70, 62, 0), (52, 62, 0), (52, 80, 0), (0, 80, 0)],
                       format="xyb", close=True, dxfattribs=a)
    msp.add_circle((30, 40), 12, dxfattribs=a)
    # slot island: centres (80, 30) and (95, 30), radius 6
    msp.add_line((80, 24), (95, 24), dxfattribs=a)
    msp.add_arc((95, 30), 6, -90, 90, dxfattribs=a)
    msp.add_line((95, 36), (80, 36), dxfattribs=a)
    msp.add_arc((80, 30), 6, 90, 270, dxfattribs=a)
    msp.add_circle((200, 200), 5, dxfattribs={"layer": "NOTES"})
    doc.saveas(path)
    return path


if __name__ == "__main__":
    make(Path(__file__).with_name("part.dxf"))
