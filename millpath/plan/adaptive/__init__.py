"""Adaptive clearing (issue 21): constant radial engagement measured on a material raster."""
