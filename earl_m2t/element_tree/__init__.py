"""The lifted model as a tree of elements, each with its path, kind, location and compared
values: what ``earl-m2t diff`` compares and what the source map of ``gen`` names."""
