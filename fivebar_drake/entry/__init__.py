"""The entry page of an output folder (`fivebar-drake index DIR`): the design's one answer, the
fix, the spec sheet, the maneuvers, the pictures and a link to every report and recording, read
from the JSON the other commands wrote (page.py)."""
