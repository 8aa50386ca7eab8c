"""Operation die-cavity (issue 6)."""
