#!/usr/bin/env bash
# Creates (once) a venv with pyshtools pinned, for gravity.pyshtools_compare.
# Exit 77 (CTest: skipped) when no venv can be made or PyPI is unreachable.
set -u
py=$1 venv=$2
pin=pyshtools==4.13.1
if [ -x "$venv/bin/python" ] && "$venv/bin/python" -c "import pyshtools, sys; sys.exit(pyshtools.__version__ != '4.13.1')" 2>/dev/null; then
  echo "pyshtools venv present: $venv"; exit 0
fi
rm -rf "$venv"
if ! "$py" -m venv "$venv"; then echo "SKIP: cannot create a venv with $py (Debian: python3-venv)"; exit 77; fi
if ! "$venv/bin/pip" install --quiet --disable-pip-version-check "$pin"; then
  echo "SKIP: pip install $pin failed (offline?)"; rm -rf "$venv"; exit 77
fi
"$venv/bin/python" -c "import pyshtools; print('pyshtools', pyshtools.__version__, 'installed in $venv')"
