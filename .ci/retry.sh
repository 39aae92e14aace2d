# Sourced by .ci/run and .ci/aarch64: `retry COMMAND...` runs a download
# (toolchains, targets) up to three times, 15 s and 30 s apart. A 503 from
# static.rust-lang.org failed a whole run once (2026-12-07) on toolchains
# the machine already had.
retry() {
  local attempt
  for attempt in 1 2 3; do
    "$@" && return 0
    [ "$attempt" -lt 3 ] && { echo "retrying in $((attempt * 15)) s: $*" >&2; sleep $((attempt * 15)); }
  done
  return 1
}
