"""Planning strategies: each is a pure function from part and parameters to a Toolpath."""
