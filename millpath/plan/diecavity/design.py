"""The finished die block as a height field: stock top outside the cavity, the cavity
floor inside (``-inf`` for a through cavity). Lengths in job units."""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Polygon


class CavityDesign:
    """``height(x, y)``: ``top`` outside ``outline`` (a shapely Polygon of the true
    curve, densely sampled), ``floor`` inside it."""

    def __init__(self, outline: Polygon, top: float, floor: float):
        self.outline = outline
        shapely.prepare(self.outline)
        self.top = float(top)
        self.floor = float(floor)

    def height(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        inside = shapely.contains_xy(self.outline, x, y)
        return np.where(inside, self.floor, self.top)
