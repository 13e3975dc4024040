"""The seed's torque analysis of the leg along a foot path, its report and plots."""
