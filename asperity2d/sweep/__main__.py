"""``python -m asperity2d.sweep run|status|report|export ...``"""

import sys

from ..cli.sweep import main

if __name__ == "__main__":
    sys.exit(main())
