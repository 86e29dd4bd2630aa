#!/usr/bin/env bash
# tools_test.sh SOURCE_DIR BUILD_DIR
#
# What every facet program's command line promises (apps/support/tool.hpp):
# --version answers and exits 0, a usage error exits 2, -q and -v and
# FACET_LOG_LEVEL set the log level, FACET_NUM_THREADS and --threads set
# the thread count; facet-view without a display says so and exits; a
# facet-bench stopped by SIGINT keeps the CSV rows it finished (exit 130);
# facet-bench --mesh measures a user's mesh.
set -uo pipefail
source_dir=$1
build=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail() { echo "FAILED: $*" >&2; exit 1; }

render="$build/apps/facet-render"
view="$build/apps/facet-view"
bench="$build/bench/facet-bench"
programs=("$render" "$view" "$bench" "$build/bench/facet-bench-shadow-ao"
          "$source_dir/plugins/facet-new-shader" "$build/libexec/facet-sandbox")
[ -x "$build/apps/facet-render-mpi" ] && programs+=("$build/apps/facet-render-mpi")

for p in "${programs[@]}"; do
  name=$(basename "$p")
  out=$("$p" --version) || fail "$name --version exited $?"
  [[ $out =~ ^$name\ [0-9]+\.[0-9]+\.[0-9]+ ]] || fail "$name --version said '$out'"
  "$p" --no-such-option > /dev/null 2>&1
  status=$?
  [ $status -eq 2 ] || fail "$name --no-such-option exited $status, not 2"
done
"$render" --msaa 3 > /dev/null 2>&1
[ $? -eq 2 ] || fail "facet-render --msaa 3 is a usage error (2)"
"$render" --size 12 > /dev/null 2>&1
[ $? -eq 2 ] || fail "facet-render --size 12 is a usage error (2)"
"$render" --help > /dev/null || fail "facet-render --help exited $?"

# Log levels: info by default; -q and FACET_LOG_LEVEL=warn leave warnings
# and errors only; -v adds debug messages.
"$render" -o a.png --size 64x36 2> default.log || fail "facet-render failed: $(cat default.log)"
grep -q "\[info\]" default.log || fail "no info lines by default"
! grep -q "\[debug\]" default.log || fail "debug lines without -v"
"$render" -o a.png --size 64x36 -q 2> quiet.log || fail "facet-render -q failed"
[ ! -s quiet.log ] || fail "facet-render -q logged: $(cat quiet.log)"
FACET_LOG_LEVEL=warn "$render" -o a.png --size 64x36 2> env.log || fail "FACET_LOG_LEVEL=warn failed"
[ ! -s env.log ] || fail "FACET_LOG_LEVEL=warn logged: $(cat env.log)"
"$render" -o a.png --size 64x36 -v 2> verbose.log || fail "facet-render -v failed"
grep -q "\[debug\] loaded shader 'unlit'" verbose.log || fail "-v shows no debug lines"
FACET_LOG_LEVEL=loud "$render" -o a.png --size 64x36 2> bad-level.log || fail "a bad level stopped it"
grep -q "FACET_LOG_LEVEL=loud: expected" bad-level.log || fail "a bad FACET_LOG_LEVEL is not said"

# Threads: FACET_NUM_THREADS, overridden by --threads; a bad value is an error.
FACET_NUM_THREADS=1 "$render" -o a.png --size 64x36 2> t1.log || fail "FACET_NUM_THREADS=1 failed"
grep -q "path on .*, 1 threads" t1.log || fail "FACET_NUM_THREADS=1 not used: $(grep path t1.log)"
FACET_NUM_THREADS=1 "$render" -o a.png --size 64x36 --threads 3 2> t3.log || fail "--threads 3 failed"
grep -q "path on .*, 3 threads" t3.log || fail "--threads 3 not used: $(grep path t3.log)"
FACET_NUM_THREADS=lots "$render" -o a.png --size 64x36 2> tbad.log
[ $? -eq 1 ] || fail "FACET_NUM_THREADS=lots should fail"
grep -q "FACET_NUM_THREADS=lots: expected a thread count 1..256" tbad.log || fail "$(cat tbad.log)"

# facet-view with no display: a clear error at once, not a silent wait.
env -u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER timeout 20 "$view" 2> view.log
status=$?
[ $status -eq 1 ] || fail "facet-view without a display exited $status: $(cat view.log)"
grep -q "no display: DISPLAY and WAYLAND_DISPLAY are unset" view.log || fail "$(cat view.log)"
env DISPLAY=:987 timeout 20 "$view" 2> view2.log
status=$?
[ $status -eq 1 ] || fail "facet-view on a display that is not there exited $status"
grep -q "display" view2.log || fail "$(cat view2.log)"

# facet-bench stopped part way keeps its finished rows, each whole.
"$bench" --scene small --shader unlit lit phong toon --size 320x180 --threads 1 --runs 400 \
         --csv rows.csv --json rows.json > bench.out 2> bench.err &
pid=$!
for _ in $(seq 600); do
  [ "$(wc -l < rows.csv 2>/dev/null || echo 0)" -ge 3 ] && break
  sleep 0.1
done
kill -INT $pid
wait $pid
status=$?
[ $status -eq 130 ] || fail "facet-bench stopped by SIGINT exited $status: $(cat bench.err)"
rows=$(($(wc -l < rows.csv) - 1))
[ $rows -ge 2 ] || fail "the CSV kept $rows rows"
fields=$(head -1 rows.csv | awk -F, '{print NF}')
awk -F, -v n="$fields" 'NF != n {exit 1}' rows.csv || fail "a CSV row is not whole: $(cat rows.csv)"
grep -q "stopped after $rows of" bench.out || fail "facet-bench did not say where it stopped: $(cat bench.out)"
grep -q "configurations 1 of" bench.err || fail "no progress lines: $(cat bench.err)"
python3 -c "import json,sys; assert len(json.load(open('rows.json'))) == $rows" ||
  fail "rows.json does not hold the $rows rows"
# With two --render settings over rounds, facet-bench prints the first's
# median over the other's, round by round: their median and range are those
# of the CSV's rows.
"$bench" --scene "$source_dir/configs/scenes/shadow.yaml" --size 160x90 --threads 1 --isa sse2 \
         --runs 2 --rounds 3 --render '{}' '{shadows: false}' --csv ratios.csv \
         --json ratios.json > ratios.out 2> ratios.err || fail "facet-bench --render: $(cat ratios.err)"
grep -q "the first render's median over each other's, per round" ratios.out ||
  fail "no ratios: $(cat ratios.out)"
python3 - ratios.csv ratios.out <<'PY' || fail "the ratios are not the rows': $(cat ratios.out)"
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["round"] != "median"]
by_round = {}
for r in rows:
    by_round.setdefault(r["round"], {})["off" if "shadows: false" in r["note"] else "on"] = float(r["median_ms"])
ratios = sorted(v["on"] / v["off"] for v in by_round.values())
assert len(ratios) == 3, ratios
line = next(l for l in open(sys.argv[2]) if l.startswith("shadow.yaml") and "{} / {shadows: false}" in l)
median, lowest, highest = (float(x) for x in line.split()[5:8])
for shown, wanted in ((median, ratios[1]), (lowest, ratios[0]), (highest, ratios[2])):
    assert abs(shown - wanted) <= 0.006, (line, ratios)
PY
# --mesh: a user's mesh as a scene of its own (alone, without --scene),
# framed and lit by one light that casts no shadow: a row a shader, named by
# the file, with its triangles, in view. Where OSMesa is built in,
# llvmpipe's worker makes the same scene again from the row, and the two
# cover the same pixels. A file that is missing or holds no mesh is an error
# naming it, before any row.
lp=()
grep -q "^OSMESA_FOUND:INTERNAL=1" "$build/CMakeCache.txt" && lp=(--llvmpipe)
"$bench" --mesh "$source_dir/assets/spot/spot.obj" --shader phong --size 160x90 --threads 1 \
         --isa sse2 --runs 1 "${lp[@]}" --csv mesh.csv --json mesh.json > mesh.out 2> mesh.err ||
  fail "facet-bench --mesh: $(cat mesh.err)"
python3 - mesh.csv "${#lp[@]}" <<'PY' || fail "facet-bench --mesh rows: $(cat mesh.csv)"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) == 1, rows
r = rows[0]
assert (r["scene"], r["shader"], r["triangles"]) == ("spot.obj", "phong", "5856"), r
assert r["note"] == "framed by its bounds; one light", r  # no shadows dropped: it casts none
if sys.argv[2] == "1":
    assert float(r["llvmpipe_median_ms"]) > 0 and r["coverage_diff_pixels"] == "0", r
    # in view (about 9% of the frame: its bounding sphere fills the height)
    assert 0.03 * 160 * 90 < int(r["covered_pixels"]) < 0.5 * 160 * 90, r
PY
"$bench" --mesh no-such.obj --size 160x90 --runs 1 > missing.out 2> missing.err
status=$?
[ $status -eq 2 ] || fail "facet-bench --mesh no-such.obj exited $status, not 2"
grep -q "no-such.obj: file not found" missing.err || fail "no error naming the mesh: $(cat missing.err)"
printf 'v 0 0 0\nf 1 2 3\n' > bad.obj
"$bench" --mesh bad.obj --size 160x90 --runs 1 --csv bad.csv > bad.out 2> bad.err
status=$?
[ $status -eq 2 ] || fail "facet-bench --mesh bad.obj exited $status, not 2"
grep -q "bad.obj: .*index out of range" bad.err || fail "no error naming bad.obj: $(cat bad.err)"
[ ! -e bad.csv ] || fail "facet-bench --mesh bad.obj wrote a CSV"
echo "tools ok"
