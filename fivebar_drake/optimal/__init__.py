"""What the legs and motors allow, apart from any controller: optimal maneuvers of the quadruped
(the vertical jump's ceiling and the torque floor of a jump to a height)."""
