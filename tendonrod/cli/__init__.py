"""The command line's subcommands, one module each by role (``solve``, ``actuate``,
``figures``, ``bench``), the scene-file helpers they share (``_common``) and the files a
solution is written to (``_output``); the parser and ``main`` are in
:mod:`tendonrod.__main__` (``python -m tendonrod``, the ``tendonrod`` script)."""
