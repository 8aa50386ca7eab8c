"""B-rep solids from STEP files (AP203, AP214, AP242) through OpenCASCADE.

- :mod:`.reader`: the solids of a file, units, setup axis, body choice, errors;
- :mod:`.faces`: face records (kind, outward normal, axis, radius, neighbours);
- :mod:`.regions`: plan-view regions (faces, sections, material above a height);
- :mod:`.holes`: round, counterbored and countersunk holes;
- :mod:`.recognise`: all machining features, as the AP224 feature model;
- :mod:`.mesh`: the solid's triangles within a chord tolerance.
"""
