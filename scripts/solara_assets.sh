#!/bin/sh
# Fill Solara's front-end asset cache from the npm registry, so the SolaraViz pages work offline.
#
# Solara loads its browser files from a CDN at run time; with no internet the page stays blank.
# Its server first looks in a cache folder (solara.server.settings.assets.proxy_cache_dir,
# normally <venv>/share/solara/cdn/). This script fills that folder with `npm pack`, one folder
# <cache>/<package>@<version>/ per package. It is idempotent: packages already there are skipped.
#
# usage: sh scripts/solara_assets.sh [PYTHON]     (default PYTHON: .venv/bin/python)
set -eu

PY=${1:-.venv/bin/python}
if ! "$PY" -c "import solara" 2>/dev/null; then
    echo "solara_assets: solara is not installed in $PY (install the viz extra: pip install -e '.[viz]')" >&2
    exit 1
fi
if ! command -v npm >/dev/null 2>&1; then
    echo "solara_assets: npm is needed to fetch Solara's browser files (apt-get install -y npm)" >&2
    exit 1
fi
CACHE=$("$PY" -c "import solara.server.settings as s; print(s.assets.proxy_cache_dir)")

# The packages (and exact versions) solara 1.64.1 asks its CDN for.
PACKAGES="@widgetti/solara-vuetify-app@10.1.1 requirejs@2.3.6 font-awesome@4.5.0 @widgetti/vue-grid-layout@2.3.13-alpha.2"

mkdir -p "$CACHE"
for spec in $PACKAGES; do
    target="$CACHE/$spec"
    if [ -d "$target" ] && [ -n "$(ls -A "$target" 2>/dev/null)" ]; then
        echo "solara_assets: $spec already in $CACHE"
        continue
    fi
    work=$(mktemp -d)
    (cd "$work" && npm pack --silent "$spec" >/dev/null)
    tarball=$(ls "$work"/*.tgz)
    mkdir -p "$work/unpacked"
    tar -xzf "$tarball" -C "$work/unpacked"
    mkdir -p "$target"
    cp -R "$work/unpacked/package/." "$target/"
    rm -rf "$work"
    echo "solara_assets: $spec -> $target"
done
echo "solara_assets: Solara's browser files are in $CACHE"
