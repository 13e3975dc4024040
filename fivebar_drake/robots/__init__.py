"""Robots built from mechanisms: layout, mass properties, SDF, plant assembly, loop closure
design."""
