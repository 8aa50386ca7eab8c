"""File formats: tool tables, tool libraries, atomic output."""
