"""Operation ``pocket`` (issue 21): offset, zigzag or adaptive clearing of drawn regions."""
