#!/usr/bin/env bash
# Fuzzes every parser of outside input with cargo-fuzz (libFuzzer):
#   fgnet_decode  FGNetFDM datagrams (FgNetFdm::decode; accepted input re-encodes identically)
#   script_parse  --script files (Script::parse; accepted scripts print and parse back equal)
#   recording_parse  recordings, fdm_run::recording (parse_recording; never panics, one-line messages)
#
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]   (default 60 s, every target)
#
# Installs what it needs: cargo-fuzz from crates.io, and a nightly toolchain if
# rustup can get one. Without nightly it builds with the stable toolchain and
# RUSTC_BOOTSTRAP=1 (which unlocks the unstable sanitizer flags cargo-fuzz passes),
# and without AddressSanitizer if even that fails.
#
# Seeds are in fuzz/corpus/<target>/ (read only); new inputs libFuzzer finds go to
# fuzz/.work/corpus/<target>/ and crashes to fuzz/artifacts/<target>/ (both ignored
# by git; copy an interesting input into fuzz/corpus/ to keep it).
#
# Runs of up to 60 s a target (CI's 60 s) build with `cargo fuzz build --dev`, the
# fuzz crate's dev profile: the release settings but fdm-core unoptimised
# (fuzz/Cargo.toml says why: optimising its fleet kernels, which no target
# reaches, took 9 of the 10 build minutes). Longer runs build with -O, fdm-core
# optimised too, for about twice script_parse's executions a second.
#
# FUZZ_STABLE=1 skips nightly and uses the stable toolchain with RUSTC_BOOTSTRAP=1.
# FUZZ_JOBS=N runs N targets at a time (default: the number of CPUs).
#
# Exit status: 0 no finding, 1 a target crashed or failed an invariant (libFuzzer
# saved the input in fuzz/artifacts/<target>/), 2 a usage error (a target that
# does not exist), 3 fuzzing could not run here (the reason is printed on a line
# starting "FUZZING NOT RUN"), 4 a target's run failed without saving an input
# (printed on a line starting "FUZZ TARGET DID NOT RUN": not a finding, but
# the target was not fuzzed).
set -uo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(fgnet_decode script_parse recording_parse dis_listener)
fi
case "$seconds" in
  ''|*[!0-9]*) echo "usage: scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]" >&2; exit 2 ;;
esac
# A target is a file of fuzz/fuzz_targets/ (a misspelt name is a usage error,
# said before anything is built, not a finding).
for target in "${targets[@]}"; do
  if [ ! -f "fuzz/fuzz_targets/$target.rs" ]; then
    known=$(cd fuzz/fuzz_targets && for f in *.rs; do printf '%s ' "${f%.rs}"; done)
    echo "usage: scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]: no target '$target' (targets: ${known% })" >&2
    exit 2
  fi
done

cannot_run() {
  echo "FUZZING NOT RUN: $*"
  exit 3
}

# cargo-fuzz
if ! cargo fuzz --version >/dev/null 2>&1; then
  echo "== installing cargo-fuzz from crates.io"
  cargo install cargo-fuzz --locked || cannot_run "cargo install cargo-fuzz failed"
fi
echo "== $(cargo fuzz --version)"

# libFuzzer is C++ (built by libfuzzer-sys).
if ! command -v c++ >/dev/null 2>&1; then
  cannot_run "no C++ compiler (c++) to build libFuzzer; install g++"
fi

# A toolchain that accepts -Z flags: nightly if present or installable, else stable
# with RUSTC_BOOTSTRAP=1.
# FUZZ_STABLE=1 skips nightly (to check the fallback).
toolchain=()
if [ "${FUZZ_STABLE:-0}" = 1 ]; then
  export RUSTC_BOOTSTRAP=1
  echo "== toolchain: FUZZ_STABLE=1; using $(rustc --version) with RUSTC_BOOTSTRAP=1"
elif rustup run nightly rustc --version >/dev/null 2>&1; then
  toolchain=(+nightly)
  echo "== toolchain: $(rustup run nightly rustc --version)"
elif timeout 300 rustup toolchain install nightly --profile minimal >/dev/null 2>&1; then
  toolchain=(+nightly)
  echo "== toolchain: $(rustup run nightly rustc --version) (installed now)"
else
  export RUSTC_BOOTSTRAP=1
  echo "== toolchain: nightly cannot be installed here; using $(rustc --version) with RUSTC_BOOTSTRAP=1"
fi

# The build: quick for short runs, fully optimised for long ones (above).
if [ "$seconds" -le 60 ]; then
  profile=(--dev)
else
  profile=(-O)
fi

# AddressSanitizer if the toolchain can build with it, else none.
sanitizer=address
echo "== building the targets (sanitizer: $sanitizer, ${profile[*]})"
if ! cargo "${toolchain[@]}" fuzz build "${profile[@]}" -s "$sanitizer" 2>/tmp/fuzz-build.$$.log; then
  tail -5 /tmp/fuzz-build.$$.log
  sanitizer=none
  echo "== AddressSanitizer build failed; building without a sanitizer"
  if ! cargo "${toolchain[@]}" fuzz build "${profile[@]}" -s none 2>/tmp/fuzz-build.$$.log; then
    tail -20 /tmp/fuzz-build.$$.log
    rm -f /tmp/fuzz-build.$$.log
    cannot_run "the fuzz targets do not build with this toolchain (see the log above)"
  fi
fi
rm -f /tmp/fuzz-build.$$.log

# The targets run side by side, FUZZ_JOBS at a time (default: the number of
# CPUs): each libFuzzer process is one thread, so on the 2-core machine two
# targets each get a core for their SECONDS, as one did alone before, in half
# the wall time.
jobs="${FUZZ_JOBS:-$(nproc)}"
case "$jobs" in
  ''|*[!0-9]*|0) echo "FUZZ_JOBS must be a positive whole number" >&2; exit 2 ;;
esac

fuzz_one() {
  local target="$1"
  local work="fuzz/.work/corpus/$target"
  mkdir -p "$work" "fuzz/artifacts/$target"
  # The seeds, where the target has some (libFuzzer refuses a directory that
  # does not exist).
  local seeds=()
  if [ -d "fuzz/corpus/$target" ]; then seeds=("fuzz/corpus/$target"); fi
  cargo "${toolchain[@]}" fuzz run "${profile[@]}" -s "$sanitizer" "$target" "$work" "${seeds[@]}" -- \
    -max_total_time="$seconds" -print_final_stats=1 2>"fuzz/.work/$target.log"
}

# The inputs libFuzzer has saved for a target (crash-, timeout-, oom-,
# leak-...): a failed run that saved none is not a finding.
artifacts() {
  find "fuzz/artifacts/$1" -type f 2>/dev/null | wc -l
}

report() {
  local target="$1" target_status="$2" saved_before="$3"
  if [ "$target_status" -eq 0 ]; then
    grep -E "stat::number_of_executed_units|stat::new_units_added" "fuzz/.work/$target.log" | sed "s/^/   $target: /"
    echo "   $target: no crash, no failed invariant"
  elif [ "$(artifacts "$target")" -gt "$saved_before" ]; then
    status=1
    tail -40 "fuzz/.work/$target.log"
    echo "FUZZ FINDING in $target: see fuzz/artifacts/$target/ and fuzz/.work/$target.log"
  else
    [ "$status" -eq 1 ] || status=4
    tail -20 "fuzz/.work/$target.log"
    echo "FUZZ TARGET DID NOT RUN: $target failed without saving an input (not a finding; see fuzz/.work/$target.log)"
  fi
}

status=0
running=()
pids=()
saved=()
finish_running() {
  local i
  for i in "${!pids[@]}"; do
    if wait "${pids[$i]}"; then
      report "${running[$i]}" 0 "${saved[$i]}"
    else
      report "${running[$i]}" 1 "${saved[$i]}"
    fi
  done
  running=()
  pids=()
  saved=()
}
for target in "${targets[@]}"; do
  if [ -d "fuzz/corpus/$target" ]; then
    echo "== fuzzing $target for ${seconds}s (seeds: fuzz/corpus/$target)"
  else
    echo "== fuzzing $target for ${seconds}s (no seeds: fuzz/corpus/$target does not exist)"
  fi
  saved+=("$(artifacts "$target")")
  fuzz_one "$target" &
  pids+=("$!")
  running+=("$target")
  if [ "${#pids[@]}" -ge "$jobs" ]; then
    finish_running
  fi
done
finish_running
exit "$status"
