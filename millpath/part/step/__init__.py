"""STEP readers.

- :mod:`.p21`: ISO 10303-21 exchange files -> instance graph (:class:`~.p21.StepFile`);
  :mod:`.writer`: the graph back to Part 21 text (round trip).
- :mod:`.ap224`: AP224 machining features, units, stock and material
  (:func:`~.ap224.read_part`); :mod:`.iso14649`: the same from ISO 14649 (STEP-NC ARM).
- :mod:`.shapes`: machinable hole, slot, pocket and face shapes in the stock frame.
- :mod:`.build`: writes AP224 feature files (fixtures, examples, benchmarks).
"""
