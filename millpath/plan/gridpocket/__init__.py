"""Free-form pockets by grid navigation: operation type ``grid-pocket``.

``cells`` (walls, offset outline, grid), ``navigate`` (window-frame order, zigzag
runs), ``zfield`` (tool-tip Z on the bottom), ``fitmotion`` (lines, arcs, cubics),
``planner`` (layers, wall pass, clean-up), ``operation`` (job keys, design).
"""
