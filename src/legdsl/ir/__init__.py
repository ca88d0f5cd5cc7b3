"""The checked intermediate representations: the creature model and the controllers, in SI units with every name resolved."""
