"""``python -m motiontool.kinematics._modelgen``: see :func:`.main.main`."""

import sys

from motiontool.kinematics._modelgen.main import main

sys.exit(main())
