"""Operation ``profile``: cut along drawn contours, outside or inside."""
