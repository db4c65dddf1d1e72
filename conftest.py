"""Settings for the whole test run (tests, doctests and the notebooks under nbval).

The kernels nbval starts inherit this process's environment: Tutorial 4's
live dashboard then shows its world without starting the agents by itself
(``autoplay``), as nobody watches a batch run.  The browser test that
measures autoplay turns it back on for the server it starts.  The live
dashboards' cache of fitted runs (``sarsp_edu.fitcache``) is off, so that
no test depends on what an earlier one fitted; the tests of the cache give
it a folder of their own.
"""

import os

os.environ["SARSP_EDU_AUTOPLAY"] = "0"
os.environ["SARSP_EDU_CACHE"] = "off"
