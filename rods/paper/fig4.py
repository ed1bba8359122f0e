"""Fig. 4 is any scene's wave-response figure and lives in :mod:`rods.study.fig4` (moved 2026-11-28); this name
stays an alias of that module for callers that import it from here (``from rods.paper import fig4``)."""

import sys

from rods.study import fig4 as _fig4

sys.modules[__name__] = _fig4
