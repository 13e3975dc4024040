"""The simulation: scenario, Drake blocks, Diagram builder, runner, statistics, recording, plots and
run comparison."""
