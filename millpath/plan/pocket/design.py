"""The designed part of a pocket operation as a height field (for the simulator)."""

from __future__ import annotations

import numpy as np
import shapely
from shapely.ops import unary_union


class PocketDesign:
    """``floor`` inside the pocket polygons (islands excluded), ``top`` elsewhere (job
    units)."""

    def __init__(self, polygons, floor: float, top: float):
        self.area = unary_union(polygons)
        shapely.prepare(self.area)
        self.floor = float(floor)
        self.top = float(top)

    def height(self, x, y):
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        inside = shapely.contains_xy(self.area, x, y)
        return np.where(inside, self.floor, self.top)
