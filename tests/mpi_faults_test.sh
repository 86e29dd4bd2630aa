#!/usr/bin/env bash
# facet-render-mpi under faults, with `mpirun -np 2`: each ends the job
# within seconds, with a non-zero status and a message that names the
# cause, and leaves no partial file.
#   - a scene that does not load (each rank finds it; one says so);
#   - a bad option;
#   - a plugin that crashes on every rank, and one that never returns
#     (the watchdog);
#   - a plugin refused by its probe frame before any rank runs it;
#   - a rank killed from outside (the job does not wait on it);
#   - SIGTERM to mpirun.
#
#   mpi_faults_test.sh SOURCE_DIR BUILD_DIR C_COMPILER
set -uo pipefail
src=$1
build=$2
cc=$3
mpi="$build/apps/facet-render-mpi"
if [ ! -x "$mpi" ] || ! command -v mpirun > /dev/null; then
  echo "facet-render-mpi or mpirun is missing: nothing to test"
  exit 0
fi
# Open MPI refuses root unless told (CI machines run as root), and a
# machine with one core has one slot.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" || exit 1

fail() { echo "FAIL: $*"; exit 1; }
# run_job SECONDS ARGS...: mpirun -np 2 facet-render-mpi ARGS, its output
# in $log and its status in $status; a job that outlives SECONDS fails.
run_job() {
  local seconds=$1 start=$SECONDS
  shift
  log=$(timeout -k 5 "$seconds" mpirun -np 2 "$mpi" "$@" 2>&1)
  status=$?
  [ $((SECONDS - start)) -lt "$seconds" ] || fail "the job outlived ${seconds}s: $*: $log"
}
# start_job ARGS...: the job in the background, its output in job.log,
# once both ranks run the plugin's code (it says "probe: shading").
start_job() {
  timeout -k 5 60 mpirun -np 2 "$mpi" "$@" > job.log 2>&1 &
  job=$!
  for _ in $(seq 200); do
    [ "$(grep -c 'probe: shading' job.log)" -ge 2 ] && return
    sleep 0.1
  done
  fail "the ranks did not start shading: $(cat job.log)"
}
# end_job SECONDS: waits for the background job, which must end within
# SECONDS; its output in $log and its status in $status.
end_job() {
  local start=$SECONDS
  wait $job
  status=$?
  log=$(cat job.log)
  [ $((SECONDS - start)) -lt "$1" ] || fail "the job took over ${1}s to end: $log"
}
expect() {  # expect WHAT TEXT: the last job failed, saying TEXT
  [ "$status" -ne 0 ] || fail "$1: exit status 0"
  [[ $log == *"$2"* ]] || fail "$1: no '$2' in: $log"
  if ls out* 2> /dev/null | grep -q part; then fail "$1: a partial file was left: $(ls)"; fi
}
probe() {  # probe FLAGS: plugins/probe.so, the test plugin built with FLAGS
  mkdir -p plugins
  "$cc" -shared -fPIC -O1 -I"$src/plugins/include" "$@" -DPLUGIN_NAME='"probe"' \
    "$src/tests/plugins/c_plugin.c" -o plugins/probe.so || fail "cannot build the test plugin"
}

printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n' > quad.obj
cat > scene.yaml << 'EOF'
render: {size: [64, 512]}
plugin_paths: [plugins]
objects:
  - {mesh: quad.obj, material: {shader: probe}}
EOF

# A scene that does not load: said once, by rank 0.
printf 'render: {size: [64, 64]\n' > broken.yaml
run_job 60 broken.yaml -o out.png
expect "a broken scene" "broken.yaml:2:1: YAML syntax error"

# A bad option: usage, status 2.
run_job 60 scene.yaml -o out.png --max-memory lots
[ "$status" -eq 2 ] || fail "a bad option: status $status: $log"
[[ $log == *"--max-memory: expected a size such as 8G"* ]] || fail "a bad option: $log"

# A crash on every rank, named with the plugin and the function.
probe -DFAULT_IN_FRAGMENT
run_job 60 scene.yaml -o out.png --band-rows 64 --no-probe
expect "a crash" "facet: shader plugin 'probe' ($work/plugins/probe.so) crashed in its fragment function: SIGSEGV"

# A call that never returns: the watchdog ends the rank, and mpirun the job.
probe -DLOOP_IN_FRAGMENT
run_job 60 scene.yaml -o out.png --band-rows 64 --no-probe --plugin-timeout 1
expect "a stall" "stalled in its fragment function: no return within 1 s; the process ends with status 70"

# The same plugin, probed: refused before any rank runs it.
run_job 60 scene.yaml -o out.png --band-rows 64 --plugin-timeout 1
expect "a probe" "its probe frame (a sphere it draws alone, in another process) failed"
[[ $log != *"probe: shading"* ]] || fail "a probed plugin ran in a rank: $log"

# A rank killed from outside while the ranks shade (in a plugin that takes
# its time): the job ends at once, rather than wait on it.
probe -DLOOP_IN_FRAGMENT
start_job scene.yaml -o out.png --band-rows 64 --no-probe --plugin-timeout 60
kill -KILL "$(pgrep -f "^$mpi scene.yaml" | head -1)"
end_job 15
[ "$status" -ne 0 ] || fail "a killed rank: exit status 0"
[[ $log == *"exited on signal 9 (Killed)"* ]] || fail "a killed rank: $log"
# What a killed rank could not remove, the next run of the image does.
next_run_cleans() {
  probe
  run_job 60 scene.yaml -o out.png --band-rows 64
  [ "$status" -eq 0 ] || fail "the run after $1: $log"
  [[ $log != *.part* ]] || [[ $log == *"which a stopped run left unfinished"* ]] ||
    fail "the run after $1: $log"
  ls | grep -q part && fail "the run after $1 left a partial file: $(ls -l | tr "\n" " "); ranks: $(pgrep -af facet-render-mpi | tr "\n" " "); $log"
  rm -f out.png
  probe -DLOOP_IN_FRAGMENT
}
next_run_cleans "a killed one"

# SIGTERM to mpirun (not to `timeout`, which would signal the ranks'
# process group too, and race mpirun's own SIGKILL): it passes SIGTERM on,
# every rank stops, and nothing is written.
start_job scene.yaml -o out.png --band-rows 64 --no-probe --plugin-timeout 60
kill -TERM "$(pgrep -P $job -x mpirun)"
end_job 15
for _ in $(seq 50); do pgrep -f "^$mpi scene.yaml" > /dev/null || break; sleep 0.1; done
if pgrep -f "^$mpi scene.yaml" > /dev/null; then fail "SIGTERM: a rank still runs 5 s on"; fi
[ "$status" -ne 0 ] || fail "SIGTERM: exit status 0"
[ ! -e out.png ] || fail "SIGTERM: an image was written"
# The ranks remove their partial files as they stop; on a loaded machine
# mpirun may kill a rank (SIGKILL, after its grace period) before it has,
# and then the next run of the image removes it.
next_run_cleans "SIGTERM"
echo "all MPI fault cases ended as they should"
exit 0
