"""RS274NGC text: the one lexer and block parser of millpath.

:mod:`millpath.gcode.lexer` reads a line into a :class:`~millpath.gcode.lexer.Block`
(words, G and M codes by modal group, parameter settings, comments) as LinuxCNC's
reader does. It sits below ``fit`` and ``interpret`` so that both read programs with
the same grammar: the interpreter executes the blocks, ``millpath fit`` follows the
position through them.
"""
