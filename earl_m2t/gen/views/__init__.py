"""One module per target: builds the plain, sorted data its templates format."""
