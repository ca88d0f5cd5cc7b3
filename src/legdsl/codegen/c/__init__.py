"""The C target: the dynamics printed as C (``dynamics.c``, ``dynamics.h``) from the Python
target's lowering, and the hand-written C runtime of the step (``runtime/``)."""
