"""The 4-DOF parallel manipulator after Pierrot (seed 004): geometry, closed-form kinematics,
Jacobians, singularities, statics, stiffness and workspace."""
