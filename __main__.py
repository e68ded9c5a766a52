"""``python -m radiometer <subcommand> [scene.blend] ...`` with bpy installed as a module."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
