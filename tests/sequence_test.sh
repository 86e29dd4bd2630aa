#!/usr/bin/env bash
# sequence_test.sh SOURCE_DIR BUILD_DIR
#
# Sequences and band-split images, end to end: facet-render's frame k is
# the same file alone and in a sequence, --resume skips what exists, a band
# render is the whole render byte for byte; and, when facet-render-mpi was
# built, `mpirun -np 2` writes the same files as one process, frames and
# bands, and a rank that fails is named with its work while the frames
# already written stay.
set -uo pipefail
source_dir=$1
build=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail() { echo "FAILED: $*" >&2; exit 1; }

render="$build/apps/facet-render"
mpi="$build/apps/facet-render-mpi"
turntable="$source_dir/configs/scenes/turntable.yaml"
shadow="$source_dir/configs/scenes/shadow.yaml"

# ---- facet-render -----------------------------------------------------------------
"$render" "$turntable" --size 160x90 --frames 0..5 -o seq_%02d.png -q || fail "the sequence"
for k in 00 01 02 03 04 05; do [ -f "seq_$k.png" ] || fail "frame $k was not written"; done
"$render" "$turntable" --size 160x90 --frames 4 -o alone_%d.png -q || fail "frame 4 alone"
cmp -s alone_4.png seq_04.png || fail "frame 4 alone differs from frame 4 in the sequence"
"$render" "$turntable" --size 160x90 --time 0.125 -o at_time.png -q || fail "--time"
cmp -s at_time.png seq_03.png || fail "--time 0.125 differs from frame 3 at 24 fps"
cmp -s seq_00.png seq_05.png && fail "frames 0 and 5 are the same: nothing moved"

# --resume: existing files are left alone, missing ones made.
rm seq_02.png
cp seq_00.png seq_03.png  # a stand-in that --resume must not replace
log=$("$render" "$turntable" --size 160x90 --frames 0..5 -o seq_%02d.png --resume 2>&1) ||
  fail "--resume: $log"
cmp -s seq_00.png seq_03.png || fail "--resume rendered frame 3 again"
[ -f seq_02.png ] || fail "--resume did not render the missing frame 2"
[[ $log == *"1 of 6 frames rendered; the others existed"* ]] || fail "--resume said: $log"
"$render" "$turntable" --size 160x90 --frames 2 -o check_%02d.png -q
cmp -s check_02.png seq_02.png || fail "frame 2 made by --resume differs"

# Bad input is a clear error.
out=$("$render" "$turntable" --frames 0..3 -o plain.png 2>&1)
[ $? -eq 2 ] && [[ $out == *"has no %d"* ]] || fail "a pattern without %d: $out"
out=$("$render" "$shadow" --frames all -o s_%d.png 2>&1)
[ $? -eq 1 ] && [[ $out == *"does not move"* ]] || fail "--frames all of a still scene: $out"
out=$("$render" "$source_dir/configs/scenes/ao.yaml" --band-rows 64 -o ao.png 2>&1)
[ $? -eq 1 ] && [[ $out == *"cannot run ambient occlusion"* ]] && [ ! -e ao.png ] ||
  fail "bands of an AO scene: $out"

# Bands: the same bytes as the whole image.
"$render" "$shadow" --size 700x530 --msaa 4 -o whole.png -q || fail "the whole image"
"$render" "$shadow" --size 700x530 --msaa 4 --band-rows 100 -o banded.png -q || fail "bands"
cmp -s whole.png banded.png || fail "the band-split image differs from the whole one"

# ---- facet-render-mpi -------------------------------------------------------------
if [ ! -x "$mpi" ] || ! command -v mpirun > /dev/null; then
  echo "facet-render-mpi or mpirun is missing: the MPI half is not run"
  exit 0
fi
# Open MPI refuses root unless told (CI machines run as root), and a
# machine with one core has one slot.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
run_mpi() { mpirun -np 2 "$mpi" "$@"; }

mkdir mpi
run_mpi "$turntable" --size 160x90 --frames 0..5 -o mpi/seq_%02d.png -q || fail "mpirun frames"
for k in 00 01 02 03 04 05; do
  [ -f "check_$k.png" ] || "$render" "$turntable" --size 160x90 --frames "$((10#$k))" -o check_%02d.png -q
  cmp -s "mpi/seq_$k.png" "check_$k.png" || fail "frame $k from two ranks differs from one process's"
done
# A skinned and morphing sequence: each rank poses its own frames.
skinning="$source_dir/configs/scenes/skinning.yaml"
run_mpi "$skinning" --size 160x90 --frames 0..3 -o mpi/skin_%d.png -q || fail "mpirun skinned frames"
"$render" "$skinning" --size 160x90 --frames 0..3 -o skin_%d.png -q || fail "the skinned sequence"
for k in 0 1 2 3; do
  cmp -s "mpi/skin_$k.png" "skin_$k.png" || fail "skinned frame $k from two ranks differs from one process's"
done
cmp -s skin_0.png skin_3.png && fail "the skinned sequence does not move"
log=$(run_mpi "$shadow" --size 700x530 --msaa 4 --band-rows 64 -o mpi/banded.png 2>&1) ||
  fail "mpirun bands: $log"
cmp -s mpi/banded.png whole.png || fail "the image from two ranks' bands differs from one process's"
[[ $log =~ rank\ 1:\ [1-9][0-9]*\ bands\ in ]] || fail "rank 1 rendered no band: $log"

# A frame that cannot be written (a folder is in its place) fails on its
# rank, which is named with the frame; the other frames are written.
mkdir fails && mkdir fails/f_3.png
log=$(run_mpi "$turntable" --size 160x90 --frames 0..5 -o fails/f_%d.png 2>&1)
[ $? -ne 0 ] || fail "a frame that failed left exit status 0"
[[ $log == *"failed on frame 3: "*"f_3.png"* ]] || fail "the failure did not name frame 3: $log"
[[ $log == *"the frames written are kept"* ]] || fail "the summary: $log"
for k in 0 1 2 4 5; do [ -f "fails/f_$k.png" ] || fail "frame $k was lost to frame 3's failure"; done
ls fails | grep -q part && fail "a partial file was left: $(ls fails)"
exit 0
