"""``python -m asperity2d.sweep run|status|report|export ...``"""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
