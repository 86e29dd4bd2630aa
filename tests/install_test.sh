#!/usr/bin/env bash
# install_test.sh SOURCE_DIR BUILD_DIR CXX
#
# Installs the build as a user would (cmake --install), moves the prefix
# elsewhere, and checks that what is installed works there and owes nothing
# to the source or build tree:
#   - facet-render renders the default scene, from a folder of its own,
#     with the sandbox, and every installed scene; facet-view starts;
#   - no installed file names the source, build or first prefix's path,
#     none is a symbolic link, and no program or plugin has a run path;
#   - pkg-config finds facet, and docs/embedding builds against the prefix
#     (find_package(facet)) and renders; so does a static link through
#     pkg-config alone; and the C example (docs/embedding/render.c), built
#     with cc through pkg-config --static, writes the default scene with
#     facet-render's pixels; and so does facet.render() of the Python
#     module in the prefix, where it was built.
set -euo pipefail
source_dir=$(readlink -f "$1")
build_dir=$(readlink -f "$2")
cxx=$3

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
step() { echo "== $*"; }

step "install into $work/first, then move it to $work/moved"
cmake --install "$build_dir" --prefix "$work/first" > "$work/install.log"
mv "$work/first" "$work/moved"
prefix=$work/moved

step "facet-render from another folder"
mkdir "$work/run"
cd "$work/run"
if ! "$prefix/bin/facet-render" -o out.png --size 64x48 2> render.log; then
  cat render.log >&2
  fail "facet-render failed"
fi
[ "$(head -c 8 out.png | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
  fail "out.png is not a PNG"
! grep -q "facet-sandbox is not installed" render.log ||
  fail "facet-render did not find libexec/facet-sandbox: $(cat render.log)"
for scene in "$prefix"/share/facet/configs/scenes/*.yaml; do  # every installed scene
  "$prefix/bin/facet-render" "$scene" -o scene.png --size 64x48 2> render.log ||
    { cat render.log >&2; fail "facet-render $scene failed"; }
done
"$prefix/bin/facet-view" --help > /dev/null || fail "facet-view --help failed"

step "nothing installed refers to the source, build or first install folder"
for path in "$source_dir" "$build_dir" "$work/first"; do
  found=$(grep -rlF "$path" "$prefix" || true)
  [ -z "$found" ] || fail "these installed files name $path:"$'\n'"$found"
done
links=$(find "$prefix" -type l)
[ -z "$links" ] || fail "symbolic links installed:"$'\n'"$links"
for file in "$prefix"/bin/* "$prefix"/libexec/* "$prefix"/lib/facet/plugins/*.so; do
  head -c 4 "$file" | grep -q ELF || continue
  ! readelf -d "$file" | grep -E "R(UN)?PATH" | grep -v '\$ORIGIN' ||
    fail "$file has a run path outside the prefix"
done

step "pkg-config"
pc=$(find "$prefix" -name facet.pc)
[ -n "$pc" ] || fail "no facet.pc installed"
export PKG_CONFIG_PATH=$(dirname "$pc")
flags=$(pkg-config --cflags --libs facet) || fail "pkg-config --cflags --libs facet failed"
echo "$flags"
[ -f "$(pkg-config --variable=includedir facet)/facet/renderer.hpp" ] ||
  fail "pkg-config's includedir has no facet/renderer.hpp"

step "docs/embedding, built against the moved prefix with find_package(facet)"
cmake -S "$source_dir/docs/embedding" -B "$work/embed" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_PREFIX_PATH="$prefix" > "$work/embed.log" ||
  { cat "$work/embed.log" >&2; fail "configuring docs/embedding failed"; }
cmake --build "$work/embed" -j2 >> "$work/embed.log" ||
  { cat "$work/embed.log" >&2; fail "building docs/embedding failed"; }
"$work/embed/embed" || fail "embed (default scene) failed"
"$work/embed/embed" "$prefix/share/facet/configs/scenes/phong.yaml" phong.png ||
  fail "embed (phong scene) failed"
[ -s phong.png ] || fail "embed wrote no phong.png"

step "docs/embedding, linked statically through pkg-config alone"
"$cxx" -std=c++20 -O1 -o "$work/embed-pc" "$source_dir/docs/embedding/main.cpp" \
       -DFACET_PREFIX_DIR="\"$(pkg-config --variable=prefix facet)\"" \
       $(pkg-config --cflags --libs --static facet) ||
  fail "a static link with pkg-config --static failed"
"$work/embed-pc" > /dev/null || fail "embed (pkg-config build) failed"

step "docs/embedding/render.c, in C99 with cc through pkg-config --static"
[ -f "$(pkg-config --variable=includedir facet)/facet/facet.h" ] || fail "facet/facet.h is not installed"
cc -std=c99 -O1 -Wall -Werror -o "$work/render-c" "$source_dir/docs/embedding/render.c" \
   -DFACET_PREFIX_DIR="\"$(pkg-config --variable=prefix facet)\"" \
   $(pkg-config --cflags --libs --static facet) || fail "building render.c with cc failed"
"$work/render-c" "" c.png 2> /dev/null && fail "render.c took an empty scene path"
"$work/render-c" "$prefix/share/facet/configs/default.yaml" c.png > /dev/null ||
  fail "render.c failed"
"$prefix/bin/facet-render" -o cli.png 2> /dev/null || fail "facet-render (default scene) failed"
# The Python module, where it was built: facet.render from the prefix.
module=$(find "$prefix/lib/python3/dist-packages" -name 'facet*.so' 2> /dev/null | head -1)
if [ -n "$module" ]; then
  step "the Python module from the prefix: facet.render(path)"
  PYTHONPATH=$(dirname "$module") /usr/bin/python3 -c '
import sys, numpy, facet
image = facet.render(sys.argv[1])
assert image.dtype == numpy.uint8 and image.ndim == 3 and image.shape[2] == 4, image.shape
image.tofile("py.rgba")
open("py.size", "w").write("%dx%d" % (image.shape[1], image.shape[0]))
' "$prefix/share/facet/configs/default.yaml" || fail "import facet; facet.render failed"
fi
raw=()
[ -f py.rgba ] && raw=(py.rgba "$(cat py.size)")
python3 "$source_dir/tests/png_pixels.py" c.png cli.png "${raw[@]}" ||
  fail "render.c's (or facet.render's) pixels differ from facet-render's"
echo "install ok"
