"""Part readers: STEP AP224 features (step/), curves given as points (curve/), surfaces (surface/)."""
