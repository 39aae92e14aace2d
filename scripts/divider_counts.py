#!/usr/bin/env python3
"""Divisions and square roots per aircraft-step of the fleet kernels, counted
as executed (BENCHMARKS.md, "Distance to the divider").

The CPU of the project's VM exposes no performance counters, so the count is
made with Valgrind: `callgrind --dump-instr=yes` gives how many times each
instruction of `fdm-fleet/examples/fleet_steps` ran; `objdump` says which of
them divide or take a square root, and how many lanes each one works on
(`vdivpd ymm`: 4 `f64` lanes, `vdivps ymm`: 8 `f32` lanes, `divsd`: 1, ...).
Two runs, of 20 and 40 steps of 1,000 aircraft, are subtracted, so the set-up
cancels and what is left is 20,000 aircraft-steps of the kernel.

Valgrind does not emulate AVX-512, so the fleets dispatch to x86-64-v3 under
it; the count of lane-operations is the algorithm's (a block's lanes are all
computed whatever the vector width), not the instruction width's.

    cargo build --release -p fdm-fleet --example fleet_steps
    python3 scripts/divider_counts.py target/release/examples/fleet_steps exact fast bourg-demo
"""

from __future__ import annotations

import collections
import os
import re
import subprocess
import sys
import tempfile

AIRCRAFT = 1000
STEPS = (20, 40)


def instructions(binary: str) -> dict[int, str]:
    """Address -> instruction text, from objdump."""
    out = subprocess.run(
        ["objdump", "-d", "--no-show-raw-insn", binary],
        check=True, capture_output=True, text=True,
    ).stdout
    table = {}
    for line in out.splitlines():
        m = re.match(r"^\s+([0-9a-f]+):\t(.*)$", line)
        if m:
            table[int(m.group(1), 16)] = m.group(2).strip()
    return table


def lane_ops(text: str) -> tuple[str, str, int] | None:
    """(`div`|`sqrt`, `f64`|`f32`, lanes) of a dividing instruction, else None."""
    op = text.split()[0] if text else ""
    if not op.startswith(("vdiv", "vsqrt", "div", "sqrt")) or op == "div":
        return None
    kind = "div" if "div" in op else "sqrt"
    precision = "f64" if op.endswith(("pd", "sd")) else "f32"
    if op.endswith(("sd", "ss")):
        return kind, precision, 1
    width = 512 if "zmm" in text else 256 if "ymm" in text else 128
    return kind, precision, width // (64 if precision == "f64" else 32)


def executed(profile: str, binary: str, table: dict[int, str]) -> collections.Counter:
    """Lane-operations executed in `binary`'s own code, from a callgrind profile."""
    counts: collections.Counter = collections.Counter()
    obj, after_call = None, False
    name = os.path.basename(binary)
    with open(profile) as f:
        for line in f:
            if line.startswith("ob="):
                obj = line.strip()[3:]
            elif line.startswith("calls="):
                after_call = True  # the next cost line is the call's inclusive cost
            elif line.startswith("0x"):
                if after_call:
                    after_call = False
                    continue
                if not obj or os.path.basename(obj) != name:
                    continue
                fields = line.split()
                ops = lane_ops(table.get(int(fields[0], 16), ""))
                if ops and len(fields) > 2:
                    kind, precision, lanes = ops
                    counts[(kind, precision)] += int(fields[2]) * lanes
    return counts


def main() -> None:
    binary, kernels = sys.argv[1], sys.argv[2:]
    table = instructions(binary)
    with tempfile.TemporaryDirectory() as tmp:
        for kernel in kernels:
            runs = []
            for steps in STEPS:
                profile = os.path.join(tmp, f"{kernel}.{steps}")
                subprocess.run(
                    ["valgrind", "--tool=callgrind", "--dump-instr=yes",
                     "--compress-pos=no", "--compress-strings=no",
                     f"--callgrind-out-file={profile}",
                     binary, kernel, str(AIRCRAFT), str(steps)],
                    check=True, capture_output=True,
                )
                runs.append(executed(profile, binary, table))
            per_step = (STEPS[1] - STEPS[0]) * AIRCRAFT
            for key in sorted(set(runs[0]) | set(runs[1])):
                value = (runs[1][key] - runs[0][key]) / per_step
                print(f"{kernel}: {key[1]} {key[0]} {value:.2f} per aircraft-step")


if __name__ == "__main__":
    main()
