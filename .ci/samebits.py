#!/usr/bin/env python3
"""Flies the thesis reference scenarios of both models with one `sim-cli`
binary and keeps every output, so that two builds (x86-64 and aarch64 under
qemu-user) can be compared byte for byte by `.ci/aarch64`.

    samebits.py [--runner CMD] SIM_CLI OUT_DIR            # fly and record
    samebits.py [--runner CMD] SIM_CLI OUT_DIR --replay-from DIR   # replay DIR/*.rec

Flying writes, per case (Palmer's four cases of reference/palmer.json, Bourg's
five of reference/bourg.json, with the commands of sim-cli/tests/cli_reference.rs):
NAME.json (the --json report), NAME.csv, NAME.rec (the recording); then, from
the same flight flown again with --fg and --dis to loopback listeners, NAME.fg
(every FGNetFDM datagram), NAME.dis (every DIS PDU), each datagram stored as a
4-byte little-endian length and its bytes, and NAME.net.json (that flight's
report without the listener's address). And fleet_MODEL.mp: the FlightGear
multiplayer datagrams of a four-aircraft fleet of each model flown 30 frames
(one second, paced) with --fg-mp.
Replaying writes NAME.replay.json and NAME.replay.csv, and fails unless the
replay exits 0 with nothing on stderr: the recording's fingerprint (its final
state and maths) matched the replaying binary's own flight.

Python's standard library only; the listeners are loopback UDP sockets with a
large receive buffer, and the number of datagrams received must equal the
number the report says were sent, so a lost datagram is an error, not a
silent difference.
"""

import argparse
import json
import pathlib
import shlex
import socket
import struct
import subprocess
import sys
import threading

ROOT = pathlib.Path(__file__).resolve().parent.parent


def fmt(value):
    """A control value as sim-cli takes it (the shortest round-trip text)."""
    return repr(float(value)) if isinstance(value, float) else str(value)


def cases():
    """(name, sim-cli arguments, script text or None) of every reference case."""
    palmer = json.loads((ROOT / "reference/palmer.json").read_text())
    for case in palmer["cases"]:
        c = case["controls"]
        yield (
            f"palmer_{case['name']}",
            ["palmer", "--headless", "--json", "--fps", str(palmer["fps"]),
             "--frames", str(palmer["frames"]),
             "--throttle", fmt(c["throttle"]), "--alpha", fmt(c["alpha"]),
             "--bank", fmt(c["bank"]), "--flaps", fmt(c["flaps"])],
            None,
        )
    bourg = json.loads((ROOT / "reference/bourg.json").read_text())
    for case in bourg["cases"]:
        yield (
            f"bourg_{case['name']}",
            ["bourg", "--headless", "--json", "--fps", str(bourg["fps"]),
             "--frames", str(bourg["frames"])],
            "".join(line + "\n" for line in case["script"]),
        )


class Listener:
    """Collects every datagram sent to a loopback UDP port."""

    def __init__(self):
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        for option in (getattr(socket, "SO_RCVBUFFORCE", None), socket.SO_RCVBUF):
            if option is None:
                continue
            try:
                self.sock.setsockopt(socket.SOL_SOCKET, option, 64 << 20)
                break
            except OSError:
                pass
        self.sock.bind(("127.0.0.1", 0))
        self.sock.settimeout(0.2)
        self.port = self.sock.getsockname()[1]
        self.datagrams = []
        self.done = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        while True:
            try:
                self.datagrams.append(self.sock.recv(65536))
            except socket.timeout:
                if self.done.is_set():
                    return

    def finish(self):
        self.done.set()
        self.thread.join()
        self.sock.close()
        return b"".join(struct.pack("<I", len(d)) + d for d in self.datagrams)


def run(command, what):
    proc = subprocess.run(command, capture_output=True)
    if proc.returncode != 0 or proc.stderr:
        sys.exit(
            f"samebits: {what}: exit status {proc.returncode}, stderr: "
            f"{proc.stderr.decode(errors='replace').strip()}"
        )
    return proc.stdout


def fly(runner, sim, out):
    for name, args, script in cases():
        if script is not None:
            script_path = out / f"{name}.txt"
            script_path.write_text(script)
            args = args + ["--script", str(script_path)]
        # The outputs on disk; the datagrams in a second flight, whose report
        # names the listeners' ports (which differ from run to run): it is
        # kept without them as NAME.net.json.
        report = run(
            runner + [sim] + args + ["--csv", str(out / f"{name}.csv"),
                                     "--record", str(out / f"{name}.rec")],
            name,
        )
        (out / f"{name}.json").write_bytes(report)
        fg, dis = Listener(), Listener()
        net = json.loads(run(
            runner + [sim] + args + ["--fg", f"127.0.0.1:{fg.port}",
                                     "--dis", f"127.0.0.1:{dis.port}"],
            f"{name} --fg --dis",
        ))
        received = {}
        for listener, key in ((fg, "fg"), (dis, "dis")):
            data = listener.finish()
            received[key] = len(listener.datagrams)
            (out / f"{name}.{key}").write_bytes(data)
        sent = {"fg": net["fg"]["sent"], "dis": net["dis"]["pdus"]}
        if received != sent:
            sys.exit(f"samebits: {name}: datagrams received {received}, sent {sent}")
        del net["dis"]["target"]
        (out / f"{name}.net.json").write_text(json.dumps(net, indent=1, sort_keys=True) + "\n")
        if script is not None:
            script_path.unlink()
        print(f"{name}: {net['frames']} frames, {sent['fg']} FGNetFDM datagrams, "
              f"{sent['dis']} DIS PDUs")


def fleet_multiplayer(runner, sim, out):
    """FlightGear multiplayer datagrams (fgnet's orientation: sines, cosines,
    acos, asin, atan2) of a small fleet of each model, one second paced."""
    for model in ("palmer", "bourg"):
        mp = Listener()
        run(runner + [sim, "fleet", "--model", model, "--aircraft", "4", "--frames", "30",
                      "--threads", "1", "--fg-mp", f"127.0.0.1:{mp.port}", "--realtime"],
            f"fleet {model} --fg-mp")
        (out / f"fleet_{model}.mp").write_bytes(mp.finish())
        if not mp.datagrams:
            sys.exit(f"samebits: fleet {model}: no multiplayer datagram received")
        print(f"fleet_{model}: {len(mp.datagrams)} multiplayer datagrams")


def replay(runner, sim, out, source):
    recordings = sorted(source.glob("*.rec"))
    if not recordings:
        sys.exit(f"samebits: no recordings in {source}")
    for rec in recordings:
        name = rec.stem
        report = run(
            runner + [sim, "replay", str(rec), "--json",
                      "--csv", str(out / f"{name}.replay.csv")],
            f"replay {rec}",
        )
        (out / f"{name}.replay.json").write_bytes(report)
        print(f"{name}: replayed, fingerprint matched")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runner", default="", help="command to run the binary with (qemu)")
    parser.add_argument("--replay-from", type=pathlib.Path)
    parser.add_argument("sim_cli")
    parser.add_argument("out", type=pathlib.Path)
    a = parser.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    runner = shlex.split(a.runner)
    if a.replay_from:
        replay(runner, a.sim_cli, a.out, a.replay_from)
    else:
        fly(runner, a.sim_cli, a.out)
        fleet_multiplayer(runner, a.sim_cli, a.out)


if __name__ == "__main__":
    main()
