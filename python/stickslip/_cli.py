"""The ``stickslip`` console script: the command line of the Rust binary, run in-process."""

import sys

from . import _stickslip


def main() -> None:
    sys.exit(_stickslip.run_cli(["stickslip", *sys.argv[1:]]))


if __name__ == "__main__":
    main()
