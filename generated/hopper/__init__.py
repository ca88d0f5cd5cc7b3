"""Generated code for the creature 'hopper' (legdsl compile); do not edit."""
