"""Compile: checked statements to plan steps, threading a ``CompileState``.

``compiler`` is the entry point; ``statement_pass`` runs one pass over a text
and holds the one table from statement type to handler; the handlers are in
``settings`` (SPEED, LET, FRAME, COMPLY), ``obstacles`` (OBSTACLE), ``blocks``
(PROC, CALL, REPEAT) and ``motion/`` (MOVE, CONTACT, SLIDE, INSERT, WAIT).
They see the pass through ``context`` only.
"""
