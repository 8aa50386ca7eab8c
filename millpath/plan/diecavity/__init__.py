"""Operation die-cavity."""
