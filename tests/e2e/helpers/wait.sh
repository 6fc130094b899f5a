# wait_until SECONDS CMD...: polls CMD every 20 ms until it succeeds; fails after SECONDS
# (a bound for a broken run, never a timing assertion: a loaded host only makes it slower).
# Sourced by both e2e helper libraries; its counters are prefixed so callers' variables survive.
wait_until() {
  _wu_lim=$(( $1 * 50 )); shift; _wu_n=0
  until "$@"; do
    _wu_n=$((_wu_n + 1)); [ $_wu_n -ge $_wu_lim ] && return 1
    sleep 0.02
  done
}
