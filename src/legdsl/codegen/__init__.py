"""Printing the lowered system as code, one sub-package per target."""
