"""The SCARA arm of seed 002 as a study of the command line (see catalog.py for the contract):
`analyze --mechanism scara` (report.md, report.json, plots) and `simulate --mechanism scara`
(a Drake Diagram following the seed's trajectory with the sized motors, summary, Rerun)."""

from fivebar_drake.mechanisms.scara import load_params
from fivebar_drake.studies.scara.report import ANALYSIS_FILES, write_analysis
from fivebar_drake.studies.scara.simulate import SIMULATION_FILES, write_simulation

__all__ = ["ANALYSIS_FILES", "SIMULATION_FILES", "load_params", "write_analysis",
           "write_simulation"]
