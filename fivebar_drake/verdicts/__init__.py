"""How a run is judged, one model for every output: the motors' checks (checks.py: torque,
speed, thermal, achieved, with their thresholds), whom a failing verdict blames and the step and
contact checks (rules.py), and summary.json's schema (summary_schema.py)."""
