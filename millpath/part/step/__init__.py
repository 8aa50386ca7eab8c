"""STEP: the ISO 10303-21 reader/writer (:mod:`.p21`, :mod:`.writer`) and the AP224
machining-feature layer (:mod:`.ap224`)."""
