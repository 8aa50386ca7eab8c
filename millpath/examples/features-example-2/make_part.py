"""Write part.stp: Azmi et al., STEP AP224 feature extraction (seeds/002), Example 2.

The paper's dimensions (its Figure 7 and the appendix "NC codes for Example2", MAHO
dialect, XZ plane): stock 300 x 150 x 25 mm (G99 ... I300 J25 K150); two holes of
diameter 16.6 mm (G89 R8.3) at x = 18.7 and x = 281.2 on the stock's mid-line, 25 mm
deep (G89 Z-25: through the 25 mm stock); a slot 25 mm wide (G87 Y25), 12.5 mm deep
(Z12.5) and 300 mm long, open at both ends, its centre line 27.5 mm from the edge
(G79 ... Z27.5; the AP224 slot placement (300.0, -27.5, 12.5) of the paper's §4.1c).
The paper's frame has Y from -150 to 0 (its hole placement (112.5, -50.00, 12.50));
here Y is shifted by +150 so the stock starts at the origin: holes at y = 75, slot
centre line at y = 122.5. The paper does not print Example 2's material; its cutting
data (F233.767 S2387.326 with an 8 mm tool: 60 m/min) match Example 1's (S763.845
with a 25 mm tool: 60 m/min), whose file designates '1020 STEEL PER MIL-S-7952'
(line #816), so that designation is used.

Run ``python make_part.py`` to rebuild part.stp.
"""

from __future__ import annotations

from pathlib import Path

from millpath.part.step.build import Ap224Builder

LENGTH, WIDTH, HEIGHT = 300.0, 150.0, 25.0
HOLE_D, HOLE_DEPTH, HOLE_X = 16.6, 25.0, (18.7, 281.2)
SLOT_W, SLOT_DEPTH, SLOT_LEN, SLOT_Y = 25.0, 12.5, 300.0, 150.0 - 27.5


def build() -> str:
    b = Ap224Builder("AP224-EXAMPLE-2", units="mm", material="1020 STEEL PER MIL-S-7952",
                     description="Azmi et al. AP224 Example 2: 300 x 150 x 25 block, two "
                                 "16.6 mm holes, 25 x 12.5 open slot")
    b.block(LENGTH, WIDTH, HEIGHT)
    for x in HOLE_X:
        b.hole((x, WIDTH / 2.0, HEIGHT), HOLE_D, HOLE_DEPTH, bottom="through")
    b.slot((0.0, SLOT_Y, HEIGHT), (1.0, 0.0), SLOT_LEN, SLOT_W, SLOT_DEPTH,
           ends=("open", "open"))
    return b.text()


if __name__ == "__main__":
    (Path(__file__).resolve().parent / "part.stp").write_text(build())
