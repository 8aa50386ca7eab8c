"""Write part.stp: Azmi et al., STEP AP224 feature extraction (seeds/002), Example 1.

The paper's numbers (§4.1 listings and the appendix "NC codes for Example1"): stock
225 x 100 x 12.5 mm (#491 length 225.00, #500 width 100.00, #482 height 12.50; G99
... I225 J12.5 K100); a 75 mm hole (#530 diameter 75.00; G89 R37.5) at x = 112.5
(#511 placement (112.5, -50.00, 12.50)), 12.5 mm deep (#541 depth 12.50), through
(#553 HOLE_BOTTOM 'through'); two 31.2 mm holes (G89 R15.6) at x = 187.5 and 37.5.
Material '1020 STEEL PER MIL-S-7952' (#816). The paper's frame has Y from -100 to 0;
here Y is shifted by +100 (holes on y = 50).

Run ``python make_part.py`` to rebuild part.stp.
"""

from __future__ import annotations

from pathlib import Path

from millpath.part.step.build import Ap224Builder


def build() -> str:
    b = Ap224Builder("PLATE-3-HOLES", units="mm", material="1020 STEEL PER MIL-S-7952",
                     description="225 x 100 x 12.5 block with three through holes")
    b.block(225.0, 100.0, 12.5)
    for x, d in ((112.5, 75.0), (187.5, 31.2), (37.5, 31.2)):
        b.hole((x, 50.0, 12.5), d, 12.5, bottom="through")
    return b.text()


if __name__ == "__main__":
    (Path(__file__).resolve().parent / "part.stp").write_text(build())
