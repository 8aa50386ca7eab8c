"""Command-line interface: one module per command, gathered by ``main``."""
