"""``python -m pymeshlab_radiance``: the command line (the same as the ``meshlab-radiance`` script)."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
