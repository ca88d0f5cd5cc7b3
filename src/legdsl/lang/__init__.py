"""The language front end: grammar loading, the parser, the syntax tree, syntax errors, units, and the error types every stage reports with."""
