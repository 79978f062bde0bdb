#!/bin/sh
# Print the path of a Python >= 3.12 interpreter, or explain what is needed and fail.
# Order: $PYTHON, pyenv's interpreter for .python-version, python3.13, python3.12, python3.
need_major=3
need_minor=12
ok() {
    "$1" -c "import sys; sys.exit(0 if sys.version_info >= ($need_major, $need_minor) else 1)" 2>/dev/null
}
candidates="${PYTHON:-}"
if command -v pyenv >/dev/null 2>&1 && [ -f .python-version ]; then
    candidates="$candidates $(pyenv prefix 2>/dev/null | cut -d: -f1)/bin/python"
fi
for v in 3.13 3.12; do
    for d in "${PYENV_ROOT:-$HOME/.pyenv}"/versions/$v*; do
        [ -x "$d/bin/python" ] && candidates="$candidates $d/bin/python"
    done
done
candidates="$candidates python3.13 python3.12 python3 python"
for c in $candidates; do
    if command -v "$c" >/dev/null 2>&1 && ok "$c"; then
        command -v "$c"
        exit 0
    fi
done
echo "error: this project needs Python >= $need_major.$need_minor (Mesa 3.5 requires it);" \
     "none was found. Install one (e.g. 'pyenv install 3.12') or set PYTHON=/path/to/python3.12." >&2
exit 1
