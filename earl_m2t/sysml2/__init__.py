"""SysML v2 textual notation: parsing with the grammar ``metamodel/grammar/sysml2.tx``."""

from earl_m2t.sysml2.parser import (
    Sysml2SyntaxError,
    doc_text,
    identification,
    literal_value,
    location,
    members,
    multiplicity,
    name_segments,
    parse_file,
    parse_text,
    rule,
    simple_name,
    unquote_name,
    unwrap,
)

__all__ = [
    "Sysml2SyntaxError",
    "doc_text",
    "identification",
    "literal_value",
    "location",
    "members",
    "multiplicity",
    "name_segments",
    "parse_file",
    "parse_text",
    "rule",
    "simple_name",
    "unquote_name",
    "unwrap",
]
