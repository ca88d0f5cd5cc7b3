"""legdsl: a compiler and runner for .leg files describing legged creatures and their control."""

__version__ = "0.1.0"
