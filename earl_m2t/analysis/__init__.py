"""Analyses behind the behaviour rules: exact reasoning over guard conditions (B006, B007)."""
