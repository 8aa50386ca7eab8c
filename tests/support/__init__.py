"""Test support shared by tests/ and bench/ (not part of the installed package):
:mod:`.difftest` compares millpath's interpreter with LinuxCNC's rs274."""
