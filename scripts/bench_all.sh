#!/usr/bin/env bash
# Runs every criterion benchmark of BENCHMARKS.md, one bench target at a time,
# logging the load average before and after each and how much CPU other
# processes took meanwhile (the machine may be shared), then redraws the fleet
# chart. Output: target/bench-logs/<UTC time>.log
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
# CPU time of the whole machine so far (user+nice+system+irq+softirq+steal), in clock ticks.
machine_busy() { awk '/^cpu /{print $2+$3+$4+$7+$8+$9}' /proc/stat; }
hz=$(getconf CLK_TCK)
out=$(mktemp)
for bench in "${benches[@]}"; do
  echo "## $bench: before: $(uptime)" | tee -a "$log"
  # The fleet bench sets its own (short) times per fleet size.
  args=(--warm-up-time 1 --measurement-time 4)
  [ "$bench" = fleet ] && args=()
  busy0=$(machine_busy); t0=$(date +%s.%N)
  TIMEFORMAT='%U %S'
  { time cargo bench --bench "$bench" -- "${args[@]}" >"$out" 2>&1; } 2>"$out.time"
  busy1=$(machine_busy); t1=$(date +%s.%N)
  grep -E '^[a-z0-9_]+(/[^ ]+)*( |$)|time:|thrpt:' "$out" | tee -a "$log"
  # What other processes used meanwhile: the machine's CPU time minus this run's.
  read -r user sys <"$out.time"
  awk -v b="$((busy1 - busy0))" -v hz="$hz" -v u="$user" -v s="$sys" -v t0="$t0" -v t1="$t1" \
    'BEGIN { w = t1 - t0; printf "## %s: other processes used %.2f cores on average (this run %.2f) over %.0f s\n", "'"$bench"'", (b / hz - u - s) / w, (u + s) / w, w }' \
    | tee -a "$log"
  echo "## $bench: after: $(uptime)" | tee -a "$log"
done
rm -f "$out" "$out.time"
if [[ " ${benches[*]} " == *" fleet "* ]]; then
  python3 scripts/fleet_chart.py --table | tee -a "$log"
fi
echo "log: $log"
