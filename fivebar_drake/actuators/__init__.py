"""The actuators: the motor law behind its gearbox (motor.py: the torque-speed envelope in both
quadrants, currents, friction, the compiled law the Diagram's motor model runs), the catalogue
of real motors and gearboxes (catalog.py) and the winding's temperature (thermal.py)."""
