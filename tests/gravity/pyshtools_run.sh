#!/usr/bin/env bash
# Runs pyshtools_compare.py with the venv's python; 77 (skipped) without the venv.
venv=$1; shift
if [ ! -x "$venv/bin/python" ]; then echo "SKIP: no pyshtools venv at $venv"; exit 77; fi
exec "$venv/bin/python" "$(dirname "$0")/pyshtools_compare.py" "$@"
