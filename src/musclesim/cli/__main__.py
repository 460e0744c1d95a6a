"""``python -m musclesim.cli``: the `musclesim` console script."""
import sys

from musclesim.cli import main

sys.exit(main())
