"""Helpers shared by the test suite (model builders, fixtures written from code)."""
