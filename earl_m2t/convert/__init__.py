"""``earl-m2t convert``: an EARL model as SysML v2 text (the subset of docs/sysml-v2.md)."""

from earl_m2t.convert.sysml import to_sysml

__all__ = ["to_sysml"]
