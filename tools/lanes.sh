#!/usr/bin/env bash
# Run shell commands on N lanes (one per core): each lane takes the next command of the
# list as soon as its previous one ends, so list the long ones first.  Each command's
# output goes to LOGDIR/NN.log; a line is printed as each starts and ends (with its time),
# then every log in list order.  Every command runs even when one fails; the exit status
# is that of the first failure in list order (0 when all pass).
#   tools/lanes.sh N LOGDIR 'command one' 'command two' ...
set -uo pipefail
LANES=$1
LOGDIR=$2
shift 2
cmds=("$@")
mkdir -p "$LOGDIR"
rm -f "$LOGDIR"/*.log "$LOGDIR"/*.rc "$LOGDIR"/next "$LOGDIR"/lock
echo 0 > "$LOGDIR/next"
t0=$SECONDS

take() {  # the index of the next command to run (one lane at a time)
  local i
  {
    flock 9
    i=$(cat "$LOGDIR/next")
    echo $((i + 1)) > "$LOGDIR/next"
  } 9> "$LOGDIR/lock"
  echo "$i"
}

lane() {
  local k=$1 i name start rc
  while :; do
    i=$(take)
    [ "$i" -lt ${#cmds[@]} ] || return 0
    name=$(printf '%02d' "$i")
    start=$SECONDS
    echo "[lane $k, $((SECONDS - t0)) s] start: ${cmds[$i]}"
    bash -c "${cmds[$i]}" > "$LOGDIR/$name.log" 2>&1
    rc=$?
    echo "$rc" > "$LOGDIR/$name.rc"
    echo "[lane $k, $((SECONDS - t0)) s] $( [ $rc = 0 ] && echo ok || echo "FAILED ($rc)" )" \
      "in $((SECONDS - start)) s: ${cmds[$i]}"
  done
}

pids=()
for k in $(seq 1 "$LANES"); do
  lane "$k" &
  pids+=($!)
done
trap 'kill "${pids[@]}" 2>/dev/null' INT TERM
wait "${pids[@]}"
status=0
for i in "${!cmds[@]}"; do
  name=$(printf '%02d' "$i")
  rc=$(cat "$LOGDIR/$name.rc" 2>/dev/null || echo 99)
  printf '\n==== %s  (exit %s)\n' "${cmds[$i]}" "$rc"
  cat "$LOGDIR/$name.log"
  if [ "$rc" != 0 ] && [ "$status" = 0 ]; then status=$rc; fi
done
echo
echo "lanes: ${#cmds[@]} commands on $LANES lanes in $((SECONDS - t0)) s"
exit "$status"
