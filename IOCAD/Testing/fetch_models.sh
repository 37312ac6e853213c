#!/bin/sh
# Fetches the STEP models of Debian's gmsh-doc package into $1 (component8.step, as1-tu-203.stp).
# Exit 77 (skip) when the package cannot be downloaded; the models are never committed.
set -u
dir=$1
mkdir -p "$dir" || exit 1
[ -s "$dir/component8.step" ] && [ -s "$dir/as1-tu-203.stp" ] && exit 0
work=$(mktemp -d) || exit 1
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1
if ! apt-get download gmsh-doc >/dev/null 2>&1; then
  echo "gmsh-doc cannot be downloaded: the real-model tests are skipped"
  exit 77
fi
dpkg -x gmsh-doc_*.deb x || exit 1
for name in component8.step as1-tu-203.stp; do
  src=$(find x -name "$name.gz" | head -n 1)
  if [ -n "$src" ]; then
    gunzip -c "$src" > "$dir/$name" || exit 1
  else
    src=$(find x -name "$name" | head -n 1)
    [ -n "$src" ] && cp "$src" "$dir/$name"
  fi
done
[ -s "$dir/component8.step" ] || { echo "component8.step not in gmsh-doc"; exit 77; }
echo "models in $dir"
