from __future__ import annotations

import sys

from fivebar_drake.launcher import main


sys.exit(main())
