#!/usr/bin/env bash
# Runs pvbatch under a virtual X server (ParaView 5.11 renders through X/GLX only).
# Usage: scripts/pvbatch-xvfb.sh SCRIPT.py [ARGS...]
# Several of these may start at once (parallel tests): each picks a random starting display
# number, and an attempt that lost the race for the X server ("bad X server connection") is
# retried; any other failure is the script's own and is returned at once.
set -u
err=$(mktemp)
trap 'rm -f "$err"' EXIT
status=1
for attempt in 1 2 3 4 5; do
  start=$((100 + RANDOM % 800))
  xvfb-run -a -n "$start" -s "-screen 0 1280x1024x24" pvbatch "$@" 2> "$err"
  status=$?
  if [ "$status" -eq 0 ] || ! grep -qiE "bad X server connection|Xvfb failed|cannot open display" "$err"; then
    cat "$err" >&2
    exit "$status"
  fi
  echo "pvbatch-xvfb: X server race (attempt $attempt), retrying" >&2
  sleep 1
done
cat "$err" >&2
exit "$status"
