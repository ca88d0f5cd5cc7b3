"""Generated code for the creature 'quadruped' (legdsl compile); do not edit."""
