"""Shared pieces of the 2.5D operations (pocket, profile): drawing keys, offsets,
the material field from the in-process stock, and a move writer with safe entries."""
