"""Generated code for the creature 'biped' (legdsl compile); do not edit."""
