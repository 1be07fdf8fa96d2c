"""earl-m2t: read EARL robot-controller models from SysML tools, check them, generate code.

Stages: read (XMI → raw index) → lift (typed EARL model) → check (rules) → generate.
"""

from earl_m2t.api import Loaded, check, load
from earl_m2t.check.engine import CheckOptions
from earl_m2t.diagnostics import Diagnostic, ModelReadError, Severity

__all__ = ["CheckOptions", "Diagnostic", "Loaded", "ModelReadError", "Severity", "check", "load"]
__version__ = "0.1.0"
