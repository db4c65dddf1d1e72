"""``python -m sarsp_edu.cli``: the ``sarsp-edu`` command."""

import sys

from .main import main

sys.exit(main())
