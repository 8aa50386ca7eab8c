"""Feature recognition speed on STEP solids of about 100, 1,000 and 10,000 faces.

Builds plates with a grid of counterbored through holes and small pockets (corner
radius 2) with OpenCASCADE (the fixture builder of tests/afr), writes each as AP214,
then times (best of ``--repeat``) reading the solid from the file
(:func:`millpath.part.brep.reader.read_solids`: OpenCASCADE's STEP reader and the Part
21 header) and recognising its features (:func:`millpath.part.brep.recognise.recognise`),
and prints faces per second. Target: a 1,000-face part recognised in under 5 s.
No peer tool recognises features from a solid in this environment (FreeCAD CAM only
finds drillable holes, interactively), so there is no side-by-side figure.
Run: ``python bench/afr_speed.py [--sizes 100,1000,10000] [--repeat 1]``.
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "afr"))


def part_of(faces: int):
    import builder
    from millpath.part.brep.faces import face_table
    # ~11.5 faces per grid cell (cylinders are two half faces; 1 cell in 3 is a pocket)
    n = max(2, int(round(math.sqrt(faces / 11.5))))
    shape = builder.many_holes(n)
    return shape, len(face_table(shape))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="100,1000,10000")
    ap.add_argument("--repeat", type=int, default=1)
    a = ap.parse_args()
    import builder
    from millpath.part.brep.reader import read_solids
    from millpath.part.brep.recognise import recognise
    print(f"{'faces':>7} {'features':>8} {'read s':>8} {'recognise s':>11} {'faces/s':>9}"
          f" {'total s':>8}")
    with tempfile.TemporaryDirectory() as d:
        for size in (int(s) for s in a.sizes.split(",")):
            shape, nf = part_of(size)
            path = builder.write_step(shape, Path(d) / f"plate_{size}.step")
            t_read = t_rec = math.inf
            for _ in range(a.repeat):
                t0 = time.process_time()
                bf = read_solids(path)
                t1 = time.process_time()
                rec = recognise(bf.bodies[0].shape)
                t2 = time.process_time()
                t_read, t_rec = min(t_read, t1 - t0), min(t_rec, t2 - t1)
            print(f"{nf:>7} {len(rec.features):>8} {t_read:>8.2f} {t_rec:>11.2f} "
                  f"{nf / t_rec:>9.0f} {t_read + t_rec:>8.2f}", flush=True)


if __name__ == "__main__":
    main()
