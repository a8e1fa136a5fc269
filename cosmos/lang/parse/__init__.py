"""Parse: program files and text to the syntax tree (:mod:`cosmos.lang.ast`), and syntax errors.

``source_file`` reads a program file, ``nesting`` bounds nesting before parsing,
``grammar`` builds Lark's parser, whose ``builder`` makes the AST with ``spans``;
``parser`` is the entry point, and ``syntax_errors`` and ``slips`` say what is wrong.
"""
