"""Free-form 2D curves from scattered points: four-point segments, C1 blends,
fewest-chord linearization and cutter offsets."""
