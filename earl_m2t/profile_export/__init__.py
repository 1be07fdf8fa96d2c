"""``earl-m2t profile``: the EARL profile of ``profiles/earl.sysml`` as a UML profile file
that Papyrus, Cameo / MagicDraw or Enterprise Architect imports.

- :mod:`.spec` turns the loaded profile into a format-neutral UML profile (stereotypes,
  extensions, tags, enumerations);
- :mod:`.formats` prepares the data of each tool format (ids, references, habits);
- :mod:`.render` fills the Jinja2 templates of ``transforms/profile/<format>/``
  (``export_profile``); it is imported on demand, so the command line starts without Jinja2.

The files are written by :func:`earl_m2t.output.write_files`.
"""

from earl_m2t.profile_export.formats import FORMATS, Target, emf_id, papyrus_ns_uri
from earl_m2t.profile_export.spec import ProfileExportError, ProfileSpec, profile_spec

__all__ = [
    "FORMATS",
    "ProfileExportError",
    "ProfileSpec",
    "Target",
    "emf_id",
    "papyrus_ns_uri",
    "profile_spec",
]
