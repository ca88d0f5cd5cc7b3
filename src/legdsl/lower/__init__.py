"""Lowering through sympy: spatial algebra, the unrolled recursions, symbolic kinematics and dynamics, and controllers."""
