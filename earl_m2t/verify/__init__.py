"""System-level model checking: the lifted model as Promela, checked by SPIN (docs/verify.md)."""
