"""Geometry shared by several layers (no imports from plan/, simulate/ or above)."""
