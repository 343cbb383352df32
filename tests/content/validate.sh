#!/bin/sh
# Runs the Khronos glTF validator on glTF files or on every .gltf in folders.
# usage: sh tests/content/validate.sh (FILE.gltf | DIR)...
set -u
if ! command -v node >/dev/null 2>&1; then
  echo "validate.sh: node is not installed; install Debian's nodejs and npm, then run tools/dev" >&2
  echo "  (or: npm install --prefix .cache/node gltf-validator)" >&2
  exit 2
fi
files=""
for arg in "$@"; do
  if [ -d "$arg" ]; then
    for f in "$arg"/*.gltf; do
      [ -e "$f" ] && files="$files $f"
    done
  else
    files="$files $arg"
  fi
done
if [ -z "$files" ]; then
  echo "validate.sh: no .gltf files in: $*" >&2
  exit 2
fi
# shellcheck disable=SC2086 # the names are ours and have no spaces
exec node "$(dirname "$0")/validate.mjs" $files
