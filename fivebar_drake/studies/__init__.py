"""End-to-end studies of the seeds' other mechanisms, one package each (see catalog.py)."""
