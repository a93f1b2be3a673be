#!/bin/sh
# The Python package against the CLI, 10^6 paper realizations to a dataset directory, paired:
#   for i in 1 2 3 4 5 6 7; do /usr/bin/time -f %e sh benches/python_vs_cli.sh python; /usr/bin/time -f %e sh benches/python_vs_cli.sh cli; done
# PYTHON: an interpreter with the package installed (default python3); STICKSLIP: the CLI binary
# (default: cargo's, through CARGO_TARGET_DIR or target/).
set -e
D=$(mktemp -d); rm -rf "$D"
if [ "$1" = python ]; then
    "${PYTHON:-python3}" -c "import stickslip, sys; stickslip.simulate(realizations=10**6, out=sys.argv[1])" "$D"
else
    "${STICKSLIP:-${CARGO_TARGET_DIR:-target}/release/stickslip}" simulate --out "$D" -q --realizations 1000000
fi
rm -rf "$D"
