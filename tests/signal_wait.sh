# tests/signal_wait.sh — sourced by the shell checks that signal a running job (render/checkpoint_checks.sh,
# mpi/mpi_checks.sh). A signal sent before the program installs its handler is lost or kills it silently (a
# background job of a non-interactive shell even starts with SIGINT ignored), and a fixed delay after the
# start was not always enough in the sanitizer build on a loaded machine. So the checks wait for the handler.

# wait_until_caught PID SIGNAL: waits (at most a minute) until /proc/PID/status shows SIGNAL (a number) among
# the caught signals (bit SIGNAL - 1 of SigCgt), then half a second more, for the program to get on with its work.
wait_until_caught() {
  local pid=$1 mask=$((1 << ($2 - 1))) caught
  for _ in $(seq 1200); do
    caught=$(awk '/^SigCgt:/ {print $2}' "/proc/$pid/status" 2>/dev/null)
    [ -n "$caught" ] && (((16#$caught & mask) != 0)) && break
    sleep 0.05
  done
  sleep 0.5
}
