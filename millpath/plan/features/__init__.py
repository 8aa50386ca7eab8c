"""Operation type ``features``: process planning and NC paths for AP224 machining
features (see :mod:`millpath.plan.features.operation`)."""
