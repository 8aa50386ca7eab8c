"""Operation ``profile`` (issue 21): cut along drawn contours, outside or inside."""
