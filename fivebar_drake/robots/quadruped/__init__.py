"""The 8-DOF quadruped with 5-bar legs."""
