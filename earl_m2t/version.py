"""earl-m2t's version, for ``--version``, the caches' keys and what it writes into its outputs."""

__version__ = "0.1.0"
