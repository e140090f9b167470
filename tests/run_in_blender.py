"""Run the Blender-tier tests inside a real Blender binary.

    blender -b --factory-startup --python-exit-code 1 --python tests/run_in_blender.py [-- PYTEST-ARGS]

The extension must already be installed (blender --command extension install-file)
into the user resources directory this Blender runs with; the tests enable it.
"""
import os
import sys

import pytest

here = os.path.dirname(os.path.abspath(__file__))
argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
os.environ["BTI_INSIDE_BLENDER"] = "1"
code = pytest.main(["-c", os.path.join(here, "pytest.ini"), "--rootdir", here,
                    os.path.join(here, "blender"), *argv])
sys.stdout.flush()
if code != 0:
    raise SystemExit(f"Blender-tier tests failed inside Blender (pytest exit code {int(code)})")
