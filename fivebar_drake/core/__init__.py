"""Generic pieces, used by every mechanism and robot: parameter validation, the motor model,
verdicts, foot-path primitives, rotations, compiled kernels, files and interrupts."""
