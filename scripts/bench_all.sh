#!/usr/bin/env bash
# Runs every criterion benchmark of BENCHMARKS.md, one bench target at a time,
# logging the load average before and after each (the machine may be shared),
# then redraws the fleet chart. Output: target/bench-logs/<UTC time>.log
#
#   scripts/bench_all.sh                 # everything, about 10 minutes
#   scripts/bench_all.sh palmer_step     # some bench targets only
set -euo pipefail
cd "$(dirname "$0")/.."

benches=("$@")
if [ ${#benches[@]} -eq 0 ]; then
  benches=(palmer_step bourg_step palmer_vs_bourg fleet fgnet_encode)
fi
mkdir -p target/bench-logs
log="target/bench-logs/$(date -u +%Y%m%dT%H%M%SZ).log"

cargo bench --no-run --workspace >/dev/null 2>&1
{
  echo "# $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores, $(rustc -V)"
  echo "# git $(git rev-parse --short HEAD)$(git diff --quiet || echo ' (dirty)')"
} | tee "$log"
for bench in "${benches[@]}"; do
  echo "## $bench: before: $(uptime)" | tee -a "$log"
  # The fleet bench sets its own (short) times per fleet size.
  args=(--warm-up-time 1 --measurement-time 4)
  [ "$bench" = fleet ] && args=()
  cargo bench --bench "$bench" -- "${args[@]}" 2>&1 \
    | grep -E '^[a-z0-9_]+(/[^ ]+)*( |$)|time:|thrpt:' | tee -a "$log"
  echo "## $bench: after: $(uptime)" | tee -a "$log"
done
if [[ " ${benches[*]} " == *" fleet "* ]]; then
  python3 scripts/fleet_chart.py --table | tee -a "$log"
fi
echo "log: $log"
