"""Operation ``pocket``: offset, zigzag or adaptive clearing of drawn regions."""
