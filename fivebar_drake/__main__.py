
from __future__ import annotations

import sys

from fivebar_drake.cli import main


sys.exit(main())
