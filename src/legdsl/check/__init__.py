"""The checker: a syntax tree in, the model and controller IR out, every user mistake as a positioned error."""
