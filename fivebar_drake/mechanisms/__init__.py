"""Mechanisms, one folder each: parameters, kinematics, Jacobians, dynamics, singularities and loop
facts."""
