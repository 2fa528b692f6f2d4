"""``python -m bench.docfigures [--check] [--root DIR]`` (the package docstring)."""

import sys

from bench.docfigures.engine import main

sys.exit(main())
