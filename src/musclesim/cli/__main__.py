"""``python -m musclesim.cli``: the `musclesim` console script."""
import sys

from musclesim.cli import main

if __name__ == "__main__":
    sys.exit(main())
