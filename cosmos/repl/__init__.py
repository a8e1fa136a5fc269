"""The interactive REPL: ``cosmos repl``.

Modules, from the outside in:

- :mod:`cosmos.repl.app`: :class:`ReplApp`, a whole session (arm, log, loop).
- :mod:`cosmos.repl.loop`: read, run, and what Ctrl-C does.
- :mod:`cosmos.repl.reader`: the prompt (history, completion, highlighting,
  toolbar, multi-line editing) or plain lines from a pipe.
- :mod:`cosmos.repl.commands`: ``:help``, ``:state``, ``:frames``, ``:load``,
  ``:reset``, ``:log``, ``:quit``.
- :mod:`cosmos.repl.engine`: compile an input against the session's state and
  run it on the arm.
- :mod:`cosmos.repl.multiline`, :mod:`~cosmos.repl.completion`,
  :mod:`~cosmos.repl.highlight`: input completeness, Tab completion, colours.
- :mod:`cosmos.repl.status`, :mod:`~cosmos.repl.names`,
  :mod:`~cosmos.repl.transcript`, :mod:`~cosmos.repl.output`: what is shown
  and kept.
"""
