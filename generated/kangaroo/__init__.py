"""Generated code for the creature 'kangaroo' (legdsl compile); do not edit."""
