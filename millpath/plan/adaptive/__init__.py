"""Adaptive clearing: constant radial engagement measured on a material raster."""
