#!/usr/bin/env bash
# check-listing.sh DOC.md ROOT
#
# A document shows a source file as a ```cpp block after a line
# `<!-- listing: PATH -->` (PATH from ROOT, the checkout): each such block
# must be the file as it is, byte for byte, so that what a reader copies
# is what builds and what the tests check.
set -euo pipefail
doc=$1
root=$2
found=0
while IFS= read -r path; do
  found=$((found + 1))
  listing=$(awk -v want="<!-- listing: $path -->" '
    $0 == want {seen = 1; next}
    seen && /^```cpp$/ {on = 1; next}
    on && /^```$/ {exit}
    on {print}' "$doc")
  if ! diff <(printf '%s\n' "$listing") "$root/$path" > /dev/null; then
    echo "$doc: the listing of $path differs from the file:" >&2
    diff <(printf '%s\n' "$listing") "$root/$path" >&2 || true
    exit 1
  fi
done < <(sed -n 's/^<!-- listing: \(.*\) -->$/\1/p' "$doc")
[ "$found" -gt 0 ] || { echo "$doc: no listings" >&2; exit 1; }
echo "$doc: $found listing(s) match"
