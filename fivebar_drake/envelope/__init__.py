"""The duty envelope of the hip motors (`fivebar-drake envelope`): a set of maneuvers, each a
named scenario, simulated on Dask through the sweep's engine; per motor and maneuver the
verdict's four checks, the maneuver that sizes each motor, the operating points over the
actuator's envelope and the winding temperature over a duty cycle."""
