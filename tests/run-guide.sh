#!/usr/bin/env bash
# run-guide.sh GUIDE.md BUILD_DIR
#
# Runs every ```sh block of a Markdown guide, in order, as one bash script
# that stops at the first failing command: from a fresh, empty HOME, in a
# folder whose ./build is BUILD_DIR, as a reader in a facet checkout would.
set -euo pipefail
guide=$(readlink -f "$1")
build=$(readlink -f "$2")

work=$(mktemp -d)
cleanup() {
  jobs -p | xargs -r kill 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
mkdir -p "$work/home" "$work/checkout"
ln -s "$build" "$work/checkout/build"

script=$(awk '/^```sh$/ {on = 1; next} /^```$/ {on = 0} on' "$guide")
[ -n "$script" ] || { echo "no sh blocks in $guide" >&2; exit 1; }
cd "$work/checkout"
HOME="$work/home" bash -euo pipefail -c "set -m; $script"
echo "guide ok: $(grep -c '^```sh$' "$guide") blocks ran"
