"""``python3 -m animanifold`` and the ``animanifold`` script: see animanifold.cli."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
