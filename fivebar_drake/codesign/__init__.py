"""Co-design of motor, gearbox and legs: a search over the actuator catalogue and parameter
paths, judged by closed-form screening and optimal-maneuver floors, every recommended design
verified by full simulation of an envelope (run.py)."""
