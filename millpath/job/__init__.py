"""Job files (TOML): stock, machine, tools and operations."""
