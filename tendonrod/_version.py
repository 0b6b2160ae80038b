"""The version of tendonrod, defined here only: pyproject.toml reads it
(``[tool.setuptools.dynamic]``), ``tendonrod.__version__`` re-exports it, and a sweep
file's fingerprint records it."""

__version__ = "0.1.0"
