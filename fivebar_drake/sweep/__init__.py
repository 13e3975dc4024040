"""Parameter sweeps of the 5-bar leg quadruped (analysis or simulation points), on Dask."""
