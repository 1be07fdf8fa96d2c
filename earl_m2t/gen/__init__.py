"""Stage 4: code generation. ``generate(model, target, out_dir)`` renders a target's
templates from a view of the model and writes them through :mod:`earl_m2t.output`."""

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.generate import GenReport, generate, render

__all__ = ["GenError", "GenReport", "generate", "render"]
