"""The runtime: actuators, ground contact, sensors, the controller's state machine, integration and recording."""
