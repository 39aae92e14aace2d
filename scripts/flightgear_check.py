#!/usr/bin/env python3
"""Live check of sim-cli's FGNetFDM v24 datagrams against a real FlightGear 2020.3.

A manual check, not run by CI (FlightGear is a 2 GB install). Python 3 standard
library only; see docs/flightgear-check.md for what it does and what it found.

Needs: fgfs 2020.3 (Debian: `apt-get install flightgear xvfb libgl1-mesa-dri xauth
dbus x11-apps`), a release build of sim-cli (`cargo build --release -p afit-fdm-cli`).

For each model it starts fgfs with the command line `sim-cli fgfs-command MODEL`
prints, adapted only for a headless machine (telnet read-back, no TerraSync, small
window, own Xvfb display, temporary FG_HOME), waits for /sim/fdm-initialized, then
for each scenario:

1. runs `sim-cli MODEL --headless --json ... --fg 127.0.0.1:RELAY` into a local UDP
   relay, which keeps every datagram (so the check sees exactly what sim-cli sent);
2. checks the datagrams (one per frame, 408 bytes, version 24) and that the last one
   is the JSON report's geodetic/attitude, encoded as docs/fgnetfdm.md says;
3. forwards them to fgfs, paced, and reads back /position and /orientation over
   telnet, comparing with the prediction of docs/fgnetfdm.md §6:
   degrees = f64(wire radians) * 57.2957763671875, altitude-ft = m * 3.28083989501312335958,
   within half a unit of the 10th significant digit telnet prints.

Plus: a direct run (sim-cli sends straight to fgfs, no relay: which frame does
FlightGear end up showing?), the negative checks of docs/fgnetfdm.md §8 (407-byte datagram,
little-endian version), and optional screenshots (xwd, converted to PNG here).

Also checked: that fgfs applied the options fgfs-command adds for the user to see the
aircraft (start view, the UFO's /sim/model/always-show-in-MP, the c172p's fuel), and that
each scenario, recorded with --record and replayed with `sim-cli replay --json --fg`,
prints the same JSON and sends byte-identical datagrams (docs/recording.md).
`--origin NAME` (e.g. phli, whose scenery Debian's data ships) flies every scenario there.
`--fleet` also streams a 4-aircraft fleet (`sim-cli fleet --fg-mp`, docs/fleet-in-flightgear.md)
into fgfs's multiplayer input and compares /ai/models/multiplayer[i]/position/* with the last
message of each callsign (1e-6 degrees).

Exit status 0 when every check passed, 1 otherwise, 2 for bad usage.
"""

import argparse
import json
import math
import os
import re
import shlex
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import zlib

R2D_FLOAT = 57.2957763671875  # SimGear's float SG_RADIANS_TO_DEGREES
M2FT = 3.28083989501312335958  # SG_METER_TO_FEET
KNOTS_PER_MPS = 3600.0 / 1852.0
METRES_PER_FOOT = 0.3048
DATAGRAM = 408

# FGNetFDM v24, every field big-endian (docs/fgnetfdm.md §3). Only the first fields are
# named; the rest are checked as a whole by size.
HEAD = struct.Struct(">II ddd f fff ff fff f f")
HEAD_NAMES = ("version padding longitude latitude altitude agl phi theta psi alpha beta "
              "phidot thetadot psidot vcas climb_rate").split()
FULL = struct.Struct(">II ddd f fff ff fff f f fff fff fff f f I 4I 4f 4f 4f 4f 4f 4f 4f "
                     "4f 4f I 4f I 3I 3f 3f 3f I i f 10f")
assert FULL.size == DATAGRAM

PROPS = {
    "latitude-deg": "/position/latitude-deg",
    "longitude-deg": "/position/longitude-deg",
    "altitude-ft": "/position/altitude-ft",
    "roll-deg": "/orientation/roll-deg",
    "pitch-deg": "/orientation/pitch-deg",
    "heading-deg": "/orientation/heading-deg",
    "airspeed-kt": "/velocities/airspeed-kt",
}

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def f32(x):
    return struct.unpack(">f", struct.pack(">f", x))[0]


def log(msg):
    print(msg, flush=True)


# ---------------------------------------------------------------- datagrams

def decode(datagram):
    return dict(zip(HEAD_NAMES, HEAD.unpack_from(datagram)))


def predict(fields):
    """What FlightGear 2020.3 should show for one datagram (docs/fgnetfdm.md §3, §6)."""
    return {
        "latitude-deg": fields["latitude"] * R2D_FLOAT,
        "longitude-deg": fields["longitude"] * R2D_FLOAT,
        "altitude-ft": fields["altitude"] * M2FT,
        "roll-deg": fields["phi"] * R2D_FLOAT,
        "pitch-deg": fields["theta"] * R2D_FLOAT,
        "heading-deg": fields["psi"] * R2D_FLOAT,
        "airspeed-kt": fields["vcas"],
    }


def make_datagram(lat_deg, lon_deg, alt_m, roll_deg=0.0, little_endian_version=False,
                  pitch_deg=0.0, heading_deg=0.0):
    """A hand-made datagram for the negative checks and for placing the viewer (all counts
    0, docs/fgnetfdm.md §5)."""
    values = [24, 0, math.radians(lon_deg), math.radians(lat_deg), alt_m, -9999.0,
              math.radians(roll_deg), math.radians(pitch_deg), math.radians(heading_deg)]
    values += [0.0] * 18 + [0] + [0] * 4 + [0.0] * 36 + [0]
    values += [0.0] * 4 + [0] + [0] * 3 + [0.0] * 9 + [0, 0, 0.0] + [0.0] * 10
    data = FULL.pack(*values)
    if little_endian_version:
        data = struct.pack("<I", 24) + data[4:]
    return data


def check_against_report(report, datagrams, frames):
    """The datagrams sim-cli sent vs its own JSON report. Returns a list of problems."""
    problems = []
    if len(datagrams) != frames:
        problems.append(f"{len(datagrams)} datagrams for {frames} frames")
    sizes = sorted({len(d) for d in datagrams})
    if sizes != [DATAGRAM]:
        problems.append(f"datagram sizes {sizes}, want [408]")
    if not datagrams:
        return problems
    last = decode(datagrams[-1])
    if (last["version"], last["padding"]) != (24, 0):
        problems.append(f"version/padding {last['version']}/{last['padding']}")
    geo, att = report["geodetic"], report["attitude_deg"]
    want = {
        "latitude": math.radians(geo["lat_deg"]),
        "longitude": math.radians(geo["lon_deg"]),
        "altitude": geo["alt_m"],
        "phi": f32(math.radians(att["roll"])),
        "theta": f32(math.radians(att["pitch"])),
        "psi": f32(math.radians(att["heading"])),
    }
    if report["model"] == "palmer":
        want["vcas"] = f32(report["airspeed"] * KNOTS_PER_MPS)
    else:
        want["vcas"] = f32(report["speed"] * METRES_PER_FOOT * KNOTS_PER_MPS)
    for name, value in want.items():
        got = last[name]
        # lat/lon/alt must be bit-exact; vcas may differ by the last f32 ulp because
        # sim-cli multiplies in a different order.
        tol = abs(value) * 2.0 ** -23 if name == "vcas" else 0.0
        if abs(got - value) > tol:
            problems.append(f"last datagram {name} = {got!r}, JSON report implies {value!r}")
    return problems


# ---------------------------------------------------------------- telnet

class Telnet:
    """FlightGear's property telnet in its default prompt mode (docs/fgnetfdm.md §7)."""

    LINE = re.compile(r"^(\S+) = '(.*)' \((\w+)\)\r\n$", re.S)

    def __init__(self, port, timeout):
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=timeout)

    def command(self, text):
        self.sock.sendall(text.encode() + b"\r\n")
        buf = b""
        while not buf.endswith(b"/> "):
            chunk = self.sock.recv(65536)
            if not chunk:
                raise ConnectionError("telnet closed")
            buf += chunk
        return buf[:-3].decode(errors="replace")

    def get(self, path):
        """(text, type) as FlightGear prints them, e.g. ('37.62499793', 'double')."""
        answer = self.command("get " + path)
        m = self.LINE.match(answer)
        if not m:
            raise ValueError(f"unexpected telnet answer {answer!r}")
        return m.group(2), m.group(3)

    def set(self, path, value):
        return self.command(f"set {path} {value}")

    def close(self):
        try:
            self.sock.sendall(b"quit\r\n")
        except OSError:
            pass
        self.sock.close()


def print_tolerance(text):
    """Half a unit of the last of the 10 significant digits telnet prints (docs/fgnetfdm.md §6)."""
    x = float(text)
    if x == 0.0:
        return 5e-10
    exponent = math.floor(math.log10(abs(x)))
    return 0.5 * 10.0 ** (exponent - 9) * (1 + 1e-9)


# ---------------------------------------------------------------- processes

def free_port(kind, below=None):
    """A free port on 127.0.0.1; `below`: one under that number (FlightGear 2020.3 keeps its
    multiplayer ports in signed 16-bit integers, so its input must be at most 32766)."""
    for port in ([0] if below is None else range(below - 1, 1024, -2)):
        s = socket.socket(socket.AF_INET, kind)
        try:
            s.bind(("127.0.0.1", port))
            return s.getsockname()[1]
        except OSError:
            continue
        finally:
            s.close()
    raise RuntimeError("no free port")


def start_xvfb(width, height):
    """Starts Xvfb on a free display number; returns (process, ':N')."""
    read_fd, write_fd = os.pipe()
    proc = subprocess.Popen(
        ["Xvfb", "-displayfd", str(write_fd), "-screen", "0", f"{width}x{height}x24",
         "-nolisten", "tcp"],
        pass_fds=(write_fd,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write_fd)
    with os.fdopen(read_fd) as f:
        number = f.readline().strip()
    if not number:
        proc.kill()
        raise RuntimeError("Xvfb did not report a display number")
    return proc, ":" + number


def stop(proc, grace=10):
    """Stops one process we started (and its own process group), by pid."""
    if proc is None or proc.poll() is not None:
        return
    try:
        os.killpg(proc.pid, 15)
    except (ProcessLookupError, PermissionError):
        proc.terminate()
    try:
        proc.wait(grace)
    except subprocess.TimeoutExpired:
        try:
            os.killpg(proc.pid, 9)
        except ProcessLookupError:
            pass
        proc.wait()


class FlightGear:
    """One fgfs process started from `sim-cli fgfs-command`."""

    # What a machine without a screen, a network or a sound card needs on top of
    # `sim-cli fgfs-command` (docs/fgnetfdm.md §7).
    def __init__(self, args, model, fps, display, workdir):
        self.args = args
        self.model = model
        self.udp_port = free_port(socket.SOCK_DGRAM)
        self.telnet_port = free_port(socket.SOCK_STREAM)
        self.mp_port = free_port(socket.SOCK_DGRAM, below=32767) if args.fleet else None
        mp = ["--fg-mp", str(self.mp_port)] if self.mp_port else []
        line = run_sim(args, ["fgfs-command", model, "--fps", str(fps),
                              "--fg", f"127.0.0.1:{self.udp_port}", "--origin", args.origin,
                              "--fgfs", args.fgfs] + mp, want_json=False).strip()
        self.ours = line
        argv = shlex.split(line)
        if argv[0] != args.fgfs:
            raise RuntimeError(f"fgfs-command printed {line!r}")
        self.headless_flags = [
            f"--telnet={self.telnet_port}", "--disable-terrasync", "--disable-clouds",
            "--disable-clouds3d", f"--geometry={args.geometry}", "--max-fps=30",
            "--disable-gui",
        ]
        if not args.draw_terrain:
            # Software GL (llvmpipe) takes minutes per frame drawing the sea at low
            # altitude with the aircraft banked; see docs/flightgear-check.md.
            self.headless_flags.append("--prop:/sim/rendering/draw-mask/terrain=false")
        if model in args.aircraft:
            # Another aircraft than fgfs-command's, e.g. for pictures.
            argv = [f"--aircraft={args.aircraft[model]}" if a.startswith("--aircraft=") else a
                    for a in argv]
        self.argv = [args.fgfs] + argv[1:] + self.headless_flags
        self.home = os.path.join(workdir, f"fg-home-{model}")
        os.makedirs(self.home, exist_ok=True)
        self.stdout_path = os.path.join(workdir, f"fgfs-{model}.out")
        self.stderr_path = os.path.join(workdir, f"fgfs-{model}.err")
        env = dict(os.environ, DISPLAY=display, FG_HOME=self.home, FG_ROOT=args.fg_root)
        cmd = self.argv
        if shutil.which("dbus-run-session"):
            cmd = ["dbus-run-session", "--"] + cmd
        log(f"[{model}] sim-cli fgfs-command: {line}")
        log(f"[{model}] starting: {' '.join(shlex.quote(a) for a in cmd)}")
        self.proc = subprocess.Popen(cmd, env=env, cwd=workdir, start_new_session=True,
                                     stdout=open(self.stdout_path, "w"),
                                     stderr=open(self.stderr_path, "w"))
        self.telnet = None

    def stderr_text(self):
        with open(self.stderr_path, errors="replace") as f:
            return f.read()

    def fgfs_log(self):
        path = os.path.join(self.home, "fgfs.log")
        if not os.path.exists(path):
            return ""
        with open(path, errors="replace") as f:
            return f.read()

    def wait_initialized(self, timeout):
        start = time.monotonic()
        while time.monotonic() - start < timeout:
            if self.proc.poll() is not None:
                rejected = re.findall(r"Unknown command-line option: ([^\s\"]+)", self.stderr_text())
                if rejected:
                    # fgfs 2020.3 shows a message box, prints its usage and exits 0.
                    raise RuntimeError(f"fgfs rejected option(s) {rejected} of: {self.ours}")
                raise RuntimeError(f"fgfs exited with status {self.proc.returncode} "
                                   f"before /sim/fdm-initialized; last stderr lines:\n"
                                   + "\n".join(self.stderr_text().splitlines()[-15:]))
            try:
                if self.telnet is None:
                    self.telnet = Telnet(self.telnet_port, self.args.telnet_timeout)
                if self.telnet.get("/sim/fdm-initialized")[0] == "true":
                    return time.monotonic() - start
            except (OSError, ValueError):
                if self.telnet is not None:
                    self.telnet.close()
                self.telnet = None
            time.sleep(2)
        raise RuntimeError(f"/sim/fdm-initialized not true after {timeout} s")

    def read(self):
        return {name: self.telnet.get(path) for name, path in PROPS.items()}

    def stop(self):
        if self.telnet is not None:
            self.telnet.close()
        stop(self.proc)


def run_sim(args, argv, want_json=True):
    out = subprocess.run([args.sim_cli] + argv, cwd=REPO, capture_output=True, text=True,
                         timeout=600)
    if out.returncode != 0:
        raise RuntimeError(f"sim-cli {' '.join(argv)} exited {out.returncode}: {out.stderr}")
    return json.loads(out.stdout) if want_json else out.stdout


def run_captured(args, argv):
    """Runs sim-cli into a local UDP relay; returns (JSON report, list of datagrams)."""
    rx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    rx.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 22)
    rx.bind(("127.0.0.1", 0))
    rx.settimeout(0.2)
    datagrams, done = [], threading.Event()

    def drain():
        while True:
            try:
                datagrams.append(rx.recv(65536))
            except socket.timeout:
                if done.is_set():
                    return

    reader = threading.Thread(target=drain)
    reader.start()
    try:
        report = run_sim(args, argv + ["--fg", f"127.0.0.1:{rx.getsockname()[1]}"])
    finally:
        done.set()
        reader.join()
        rx.close()
    return report, datagrams


def send(port, datagrams, pace):
    tx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    for d in datagrams:
        tx.sendto(d, ("127.0.0.1", port))
        if pace:
            time.sleep(pace)
    tx.close()


def compare(readback, expected):
    """Per property: FlightGear's text, the prediction, the difference, the tolerance."""
    rows = {}
    for name, (text, kind) in readback.items():
        got = float(text)
        want = expected[name]
        tol = print_tolerance(text)
        rows[name] = {"fg": text, "type": kind, "predicted": want, "diff": got - want,
                      "tolerance": tol, "ok": abs(got - want) <= tol}
    return rows


def matching_frame(readback, datagrams):
    """Index (0-based) of the datagram whose prediction matches what FG shows."""
    for i in range(len(datagrams) - 1, -1, -1):
        rows = compare(readback, predict(decode(datagrams[i])))
        if all(r["ok"] for r in rows.values()):
            return i
    return None


# ---------------------------------------------------------------- screenshots

def xwd_to_png(xwd, path):
    """Converts an `xwd` dump (ZPixmap, 24/32 bits per pixel) to PNG, stdlib only."""
    header = struct.unpack_from(">25I", xwd)
    (header_size, _version, pixmap_format, _depth, width, height, _xoff, byte_order,
     _unit, _bit_order, _pad, bits_per_pixel, bytes_per_line, _vclass, red_mask,
     green_mask, blue_mask, _bits_rgb, _cmap_entries, ncolors) = header[:20]
    if pixmap_format != 2 or bits_per_pixel not in (24, 32):
        raise ValueError(f"unsupported xwd: format {pixmap_format}, {bits_per_pixel} bpp")
    data = xwd[header_size + 12 * ncolors:]
    step = bits_per_pixel // 8
    endian = "little" if byte_order == 0 else "big"

    def shift(mask):
        return (mask & -mask).bit_length() - 1

    shifts = [(m, shift(m)) for m in (red_mask, green_mask, blue_mask)]
    rows = []
    for y in range(height):
        line = data[y * bytes_per_line:y * bytes_per_line + width * step]
        row = bytearray(b"\x00")
        for x in range(0, width * step, step):
            p = int.from_bytes(line[x:x + step], endian)
            row += bytes(((p & m) >> s) & 0xFF for m, s in shifts)
        rows.append(bytes(row))

    def chunk(kind, body):
        return (struct.pack(">I", len(body)) + kind + body
                + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def screenshot(display, path):
    xwd = subprocess.run(["xwd", "-display", display, "-name", "FlightGear", "-silent"],
                         capture_output=True, timeout=60)
    if xwd.returncode != 0:
        raise RuntimeError(f"xwd failed: {xwd.stderr.decode(errors='replace')}")
    xwd_to_png(xwd.stdout, path)


# ---------------------------------------------------------------- the check

SCENARIOS = {
    "palmer": [
        ("palmer-climb", ["--fps", "10", "--frames", "600", "--throttle", "1", "--alpha", "4",
                          "--bank", "5"]),
        ("palmer-bank20", ["--fps", "10", "--frames", "600", "--throttle", "1", "--alpha", "4",
                           "--bank", "20"]),
    ],
    "bourg": [
        ("bourg-roll", ["--fps", "30", "--frames", "900", "--script",
                        "examples/scripts/bourg_roll.txt"]),
        ("bourg-roll-right", ["--fps", "30", "--frames", "290", "--script",
                              "examples/scripts/bourg_roll.txt"]),
    ],
}


def check_replay(args, model, argv, report, datagrams):
    """Records the scenario again and replays it: same JSON, same datagrams (bytes)."""
    path = os.path.join(args.workdir_path, f"{model}-replay.rec")
    recorded, recorded_datagrams = run_captured(
        args, [model, "--headless", "--json", "--record", path] + argv)
    replayed, replayed_datagrams = run_captured(args, ["replay", path, "--json"])
    problems = []
    if recorded != report or recorded_datagrams != datagrams:
        problems.append("recording the run changed its report or datagrams")
    if replayed != report:
        problems.append("replay report differs from the run's")
    if replayed_datagrams != datagrams:
        problems.append(f"replay sent {len(replayed_datagrams)} datagrams, not the run's "
                        f"{len(datagrams)} identical ones")
    log(f"   replay of {os.path.getsize(path)}-byte recording: "
        f"{'identical' if not problems else '; '.join(problems)}")
    return problems


def ecef_to_geodetic(x, y, z):
    """WGS-84 latitude, longitude (degrees) and height (m) of an ECEF point."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    lon = math.atan2(y, x)
    p = math.hypot(x, y)
    lat = math.atan2(z, p * (1 - e2))
    for _ in range(10):
        n = a / math.sqrt(1 - e2 * math.sin(lat) ** 2)
        h = p / math.cos(lat) - n
        lat = math.atan2(z, p * (1 - e2 * n / (n + h)))
    n = a / math.sqrt(1 - e2 * math.sin(lat) ** 2)
    return math.degrees(lat), math.degrees(lon), p / math.cos(lat) - n


def geodetic_to_ecef(lat_deg, lon_deg, h):
    """ECEF metres of a WGS-84 latitude, longitude (degrees) and height (m)."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    lat, lon = math.radians(lat_deg), math.radians(lon_deg)
    n = a / math.sqrt(1 - e2 * math.sin(lat) ** 2)
    return ((n + h) * math.cos(lat) * math.cos(lon), (n + h) * math.cos(lat) * math.sin(lon),
            (n * (1 - e2) + h) * math.sin(lat))


def closest_on_track(track, point, frame_s):
    """The point of a callsign's streamed track nearest to `point` (all ECEF): FlightGear
    draws a multiplayer aircraft at its messages interpolated linearly in ECEF at its own
    clock minus a lag, or extrapolated past the last one, so what it shows lies on the
    polyline of the messages or on the continuation of its last segment. Returns (the ECEF
    point, its time relative to the last message in seconds)."""
    best = None
    n = len(track)
    for k in range(max(0, n - 300), n - 1):
        p, q = track[k], track[k + 1]
        d = [q[i] - p[i] for i in range(3)]
        dd = sum(c * c for c in d)
        u = 0.0 if dd == 0 else sum((point[i] - p[i]) * d[i] for i in range(3)) / dd
        # Inside the segment, or (last one) up to 10 s of extrapolation past its end.
        u = max(0.0, min(u, 1.0 if k < n - 2 else 1.0 + 10.0 / frame_s))
        c = [p[i] + u * d[i] for i in range(3)]
        dist = math.dist(c, point)
        if best is None or dist < best[0]:
            best = (dist, c, (k + u - (n - 1)) * frame_s)
    return best[1], best[2]


def fleet_check(args, fg, model, results):
    """`sim-cli fleet --fg-mp` through a relay into fgfs's multiplayer input: the position
    FlightGear shows under /ai/models/multiplayer[i] must be on the callsign's streamed track,
    within 1e-6 degrees (and 1e-3 ft) of the nearest point of it (FlightGear shows
    multiplayer aircraft a little in the past, interpolating between messages)."""
    rx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    rx.bind(("127.0.0.1", 0))
    rx.settimeout(0.2)
    tx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    last, tracks, done = {}, {}, threading.Event()

    def relay():
        while True:
            try:
                d = rx.recv(65536)
            except socket.timeout:
                if done.is_set():
                    return
                continue
            tx.sendto(d, ("127.0.0.1", fg.mp_port))  # forwarded at once: real-time pace kept
            callsign = d[24:32].rstrip(b"\0").decode()
            last[callsign] = struct.unpack(">3d", d[144:168])
            tracks.setdefault(callsign, []).append(last[callsign])

    thread = threading.Thread(target=relay)
    thread.start()
    script = ("examples/scripts/palmer_climb_turn.txt" if model == "palmer"
              else "examples/scripts/bourg_roll.txt")
    argv = ["fleet", "--model", model, "--aircraft", "4", "--frames", str(args.fleet_frames),
            "--pattern", "rows", "--origin", args.origin, "--script", script,
            "--fg-mp", f"127.0.0.1:{rx.getsockname()[1]}", "--realtime", "--json"]
    # Read FlightGear back while the fleet is still streaming (two thirds of the way), so
    # it shows the aircraft between two received messages rather than extrapolated past
    # the last one; `ls` gives all of an aircraft's position properties from one frame.
    # The viewer's own aircraft back at the fleet's start (one frame, straight to fgfs), so
    # the chase view behind it looks at the fleet.
    run_sim(args, [model, "--headless", "--json", "--frames", "1", "--origin", args.origin,
                   "--fg", f"127.0.0.1:{fg.udp_port}"])
    proc = subprocess.Popen([args.sim_cli] + argv, cwd=REPO, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    shown_at = {}
    try:
        time.sleep(args.fleet_frames / 30 * 2 / 3)
        for i in range(8):
            base = f"/ai/models/multiplayer[{i}]"
            listing = fg.telnet.command(f"ls {base}/position")
            values = dict(re.findall(r"^(\S+) =\s+'([^']*)'", listing, re.M))
            callsign = fg.telnet.get(f"{base}/callsign")[0]
            if all(k in values for k in ("latitude-deg", "longitude-deg", "altitude-ft")):
                # Messages of this callsign forwarded by then (the relay's list grows).
                received = len(tracks.get(callsign, []))
                shown_at[callsign] = (base, received, {k: float(values[k]) for k in
                                                       ("latitude-deg", "longitude-deg",
                                                        "altitude-ft")})
        if args.screenshots:
            # The viewer's aircraft put 100 m south of the fleet's middle at its height,
            # heading north, and its own view (view 0): the fleet's rows are 50 to 150 m
            # ahead. Best with the UFO as viewer (it has no cockpit in the way).
            os.makedirs(args.screenshots, exist_ok=True)
            mid = [sum(t[-1][i] for t in tracks.values()) / len(tracks) for i in range(3)]
            lat, lon, h = ecef_to_geodetic(*mid)
            send(fg.udp_port, [make_datagram(lat - 100 / 110_750, lon, h)], 0)
            fg.telnet.set("/sim/current-view/view-number", 0)
            fg.telnet.set("/sim/current-view/pitch-offset-deg", 0)
            fg.telnet.set("/sim/current-view/heading-offset-deg", 0)
            time.sleep(2)  # the models load in the background
            path = os.path.join(args.screenshots, f"fleet-{model}.png")
            screenshot(args.display_used, path)
            log(f"   screenshot {path} ({os.path.getsize(path)} bytes)")
            fg.telnet.set("/sim/current-view/view-number", 2)
        out, err = proc.communicate(timeout=600)
    finally:
        if proc.poll() is None:
            proc.kill()
        done.set()
        thread.join()
        rx.close()
        tx.close()
    if proc.returncode != 0:
        raise RuntimeError(f"sim-cli {' '.join(argv)} exited {proc.returncode}: {err}")
    report = json.loads(out)
    rows, ok = {}, len(last) == 4
    for callsign, (base, received, got) in sorted(shown_at.items()):
        if callsign not in tracks or received < 2:
            continue
        shown = geodetic_to_ecef(got["latitude-deg"], got["longitude-deg"],
                                 got["altitude-ft"] / M2FT)
        nearest, t_rel = closest_on_track(tracks[callsign][:received], shown, 1 / 30)
        lat, lon, h = ecef_to_geodetic(*nearest)
        diffs = {"latitude-deg": got["latitude-deg"] - lat,
                 "longitude-deg": got["longitude-deg"] - lon,
                 "altitude-ft": got["altitude-ft"] - h * M2FT}
        # 1e-6 degrees of latitude is 0.11 m: the same distance vertically, 0.36 ft.
        good = (abs(diffs["latitude-deg"]) <= 1e-6 and abs(diffs["longitude-deg"]) <= 1e-6
                and abs(diffs["altitude-ft"]) <= 0.11 * M2FT)
        rows[callsign] = {"fg": got, "on_track": [lat, lon, h * M2FT], "diff": diffs,
                          "track_time_s": t_rel, "messages": received, "ok": good}
        log(f"   {base} {callsign}: " + ", ".join(f"{k} {v:+.1e}" for k, v in diffs.items())
            + f" (track point {t_rel:+.3f} s from the last message received)"
            + (" ok" if good else " MISMATCH"))
        ok &= good
    ok &= len(rows) == 4
    results.setdefault("fleet", {})[model] = {"sim_cli": argv, "report": report,
                                              "aircraft": rows, "ok": ok}
    log(f"\n== fleet ({model}): {len(rows)} of 4 multiplayer aircraft read back: "
        + ("ok" if ok else "FAILED"))
    return ok


def check_options(fg, model, results):
    """fgfs applied the options fgfs-command adds so that the aircraft can be seen."""
    expected = {"/sim/current-view/view-number": "2"}
    if model == "bourg":
        expected["/sim/model/always-show-in-MP"] = "true"
    if fg.mp_port is not None:
        # fgfs-command --fg-mp: multiplayer aircraft drawn with their own models within 5 km.
        expected["/sim/rendering/static-lod/aimp-range-mode-distance"] = "true"
        expected["/sim/rendering/static-lod/aimp-detailed"] = "5000"
    if model == "palmer":
        expected["/consumables/fuel/tank[0]/level-gal_us"] = "20"
        expected["/consumables/fuel/tank[1]/level-gal_us"] = "20"
    # fgfs-command's Nasal start-up script sets them 1 s after the FDM is
    # initialised: allow it 20 s of simulated start-up.
    deadline = time.time() + 20
    while True:
        rows = {}
        for path, want in expected.items():
            got = fg.telnet.get(path)[0]
            same = got == want or (want.replace(".", "").isdigit() and float(got) == float(want))
            rows[path] = {"fg": got, "expected": want, "ok": same}
        if all(r["ok"] for r in rows.values()) or time.time() > deadline:
            break
        time.sleep(1)
    for path, r in rows.items():
        log(f"   {path} = {r['fg']!r} (want {r['expected']!r}) {'ok' if r['ok'] else 'MISMATCH'}")
    results.setdefault("options", {})[model] = rows
    return all(r["ok"] for r in rows.values())


def run_scenario(args, fg, name, model, argv, results):
    argv = argv + ["--origin", args.origin]
    frames = int(argv[argv.index("--frames") + 1])
    report, datagrams = run_captured(args, [model, "--headless", "--json"] + argv)
    problems = check_against_report(report, datagrams, frames)
    replay = check_replay(args, model, argv, report, datagrams)
    problems += replay
    fg.telnet.get("/sim/time/elapsed-sec")  # let FG finish the previous frame
    send(fg.udp_port, datagrams, args.pace)
    time.sleep(args.settle)
    readback = fg.read()
    rows = compare(readback, predict(decode(datagrams[-1])))
    shown = matching_frame(readback, datagrams)
    ok = not problems and all(r["ok"] for r in rows.values())
    results["scenarios"][name] = {
        "sim_cli": ["sim-cli", model, "--headless", "--json"] + argv,
        "datagrams": len(datagrams), "report": {k: report[k] for k in ("geodetic", "attitude_deg")},
        "problems": problems, "properties": rows,
        "frame_shown": None if shown is None else shown + 1, "ok": ok,
    }
    log(f"\n== {name}: sim-cli {model} {' '.join(argv)}  ({len(datagrams)} datagrams)")
    for p in problems:
        log(f"   PROBLEM {p}")
    log(f"   {'property':14} {'FlightGear':>16} {'predicted':>22} {'diff':>10} {'tol':>8}")
    for prop, r in rows.items():
        log(f"   {prop:14} {r['fg']:>16} {r['predicted']:>22.15g} {r['diff']:>10.2e} "
            f"{r['tolerance']:>8.1e} {'ok' if r['ok'] else 'MISMATCH'}")
    if shown is not None and shown != len(datagrams) - 1:
        log(f"   FlightGear shows frame {shown + 1} of {len(datagrams)}")
    return ok


def direct_run(args, fg, results):
    """sim-cli sending straight to fgfs, as fast as it can: which frame does FG show?"""
    argv = SCENARIOS["palmer"][0][1] + ["--origin", args.origin]
    _, datagrams = run_captured(args, ["palmer", "--headless", "--json"] + argv)
    fg.telnet.get("/sim/time/elapsed-sec")
    run_sim(args, ["palmer", "--headless", "--json"] + argv
            + ["--fg", f"127.0.0.1:{fg.udp_port}"])
    time.sleep(args.settle)
    readback = fg.read()
    shown = matching_frame(readback, datagrams)
    results["direct"] = {"frames": len(datagrams), "frame_shown": None if shown is None else shown + 1}
    log(f"\n== direct: sim-cli palmer {' '.join(argv)} --fg 127.0.0.1:{fg.udp_port} (no relay)")
    if shown is None:
        log("   FlightGear shows none of the frames sim-cli sent")
    else:
        log(f"   FlightGear shows frame {shown + 1} of {len(datagrams)}"
            + ("" if shown == len(datagrams) - 1 else
               " (not the last: the burst overflowed the receive buffer)"))


def negative_checks(args, fg, results):
    """docs/fgnetfdm.md §8 step 4: both must leave the properties as they were."""
    ok = True
    before = fg.read()
    elsewhere = dict(lat_deg=39.9, lon_deg=-84.0, alt_m=1234.5, roll_deg=-33.0)
    checks = {
        "407-byte datagram": (make_datagram(**elsewhere)[:407], "read() not enough bytes",
                              fg.fgfs_log),
        "little-endian version": (make_datagram(little_endian_version=True, **elsewhere),
                                  "read 402653184 need 24", fg.stderr_text),
    }
    results["negative"] = {}
    for name, (data, message, source) in checks.items():
        send(fg.udp_port, [data], 0)
        time.sleep(args.settle)
        after = fg.read()
        unchanged = after == before
        logged = message in source()
        results["negative"][name] = {"unchanged": unchanged, "logged": logged,
                                     "message": message}
        log(f"\n== negative: {name}: properties unchanged {unchanged}, "
            f"log has {message!r}: {logged}")
        ok &= unchanged and logged
    return ok


def take_screenshot(args, fg, display, stem):
    """The last state FlightGear was sent, seen from behind and from the left.

    Helicopter view (view 1): heading offset 0 looks along the heading from behind,
    270 from the aircraft's left side. The terrain (here: sea) is drawn for the
    horizon unless --screenshot-no-terrain."""
    if not args.screenshot_no_terrain:
        fg.telnet.set("/sim/rendering/draw-mask/terrain", "true")
    fg.telnet.set("/sim/current-view/view-number", 1)
    paths = []
    for label, offset in (("behind", 0), ("left", 270)):
        fg.telnet.set("/sim/current-view/heading-offset-deg", offset)
        for _ in range(args.screenshot_frames):
            fg.telnet.get("/sim/time/elapsed-sec")  # one answer per rendered frame or so
        time.sleep(1)
        path = f"{stem}-{label}.png"
        screenshot(display, path)
        log(f"   screenshot {path} ({os.path.getsize(path)} bytes)")
        paths.append(path)
    fg.telnet.set("/sim/current-view/heading-offset-deg", 0)
    fg.telnet.set("/sim/current-view/view-number", 0)
    if not args.draw_terrain:
        fg.telnet.set("/sim/rendering/draw-mask/terrain", "false")
    return paths


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--fgfs", default="/usr/games/fgfs")
    p.add_argument("--origin", default="wpafb",
                   help="sim-cli --origin for FlightGear and every scenario (default wpafb; "
                        "phli and bikf have scenery in Debian's data)")
    p.add_argument("--fg-root", default="/usr/share/games/flightgear")
    p.add_argument("--sim-cli", default=os.path.join(REPO, "target/release/sim-cli"))
    p.add_argument("--models", default="palmer,bourg", help="comma-separated")
    p.add_argument("--geometry", default="480x360", help="fgfs window size")
    p.add_argument("--display", help="use this X display instead of starting Xvfb")
    p.add_argument("--draw-terrain", action="store_true",
                   help="keep drawing the terrain (very slow with software GL)")
    p.add_argument("--pace", type=float, default=0.002,
                   help="seconds between forwarded datagrams (default 0.002)")
    p.add_argument("--settle", type=float, default=3.0,
                   help="seconds to wait after sending before reading back")
    p.add_argument("--init-timeout", type=float, default=600)
    p.add_argument("--telnet-timeout", type=float, default=120)
    p.add_argument("--no-direct", action="store_true", help="skip the direct (no relay) run")
    p.add_argument("--fleet", action="store_true",
                   help="also stream a 4-aircraft fleet (sim-cli fleet --fg-mp) into fgfs's "
                        "multiplayer input and read /ai/models/multiplayer[i] back")
    p.add_argument("--fleet-frames", type=int, default=300,
                   help="frames the fleet flies (30 per second; default 300)")
    p.add_argument("--screenshots", metavar="DIR",
                   help="write PNGs of the chase view after palmer-bank20 and bourg-roll-right")
    p.add_argument("--screenshot-no-terrain", action="store_true",
                   help="do not draw the terrain (sea) for the screenshots")
    p.add_argument("--screenshot-frames", type=int, default=20,
                   help="telnet round trips to wait before each screenshot")
    p.add_argument("--aircraft", action="append", default=[], metavar="MODEL=NAME",
                   help="show MODEL as fgfs aircraft NAME instead of fgfs-command's choice "
                        "(e.g. bourg=c172p)")
    p.add_argument("--workdir", help="keep logs and FG_HOME here (default: a temp dir)")
    p.add_argument("--json", metavar="FILE", help="write the results as JSON")
    args = p.parse_args()

    try:
        args.aircraft = dict(a.split("=", 1) for a in args.aircraft)
    except ValueError:
        p.error("--aircraft wants MODEL=NAME")
    for tool in (args.fgfs, args.sim_cli):
        if not os.access(tool, os.X_OK):
            p.error(f"{tool} is not executable")
    workdir = args.workdir or tempfile.mkdtemp(prefix="fgcheck-")
    os.makedirs(workdir, exist_ok=True)
    args.workdir_path = workdir
    log(f"work directory (logs, FG_HOME): {workdir}")
    width, height = (int(v) for v in args.geometry.split("x"))
    xvfb, display = (None, args.display) if args.display else start_xvfb(width, height)
    log(f"X display {display}")
    args.display_used = display
    results = {"scenarios": {}}
    ok = True
    try:
        for model in args.models.split(","):
            scenarios = SCENARIOS[model]
            fps = int(scenarios[0][1][scenarios[0][1].index("--fps") + 1])
            fg = FlightGear(args, model, fps, display, workdir)
            try:
                took = fg.wait_initialized(args.init_timeout)
                log(f"[{model}] /sim/fdm-initialized after {took:.0f} s")
                ok &= check_options(fg, model, results)
                # "Out of fuel!" before the fuel is in is expected; none after.
                dry_before = fg.stderr_text().count("Out of fuel!")
                results.setdefault("fgfs", {})[model] = {"command": fg.ours,
                                                        "headless_flags": fg.headless_flags}
                for name, argv in scenarios:
                    ok &= run_scenario(args, fg, name, model, argv, results)
                    if args.screenshots and name in ("palmer-bank20", "bourg-roll-right"):
                        os.makedirs(args.screenshots, exist_ok=True)
                        take_screenshot(args, fg, display, os.path.join(args.screenshots, name))
                if args.fleet:
                    ok &= fleet_check(args, fg, model, results)
                if model == "palmer":
                    # The c172p's engine.nas logs this whenever the engine runs dry.
                    dry = fg.stderr_text().count("Out of fuel!") - dry_before
                    results["out_of_fuel_messages"] = dry
                    log(f"\n== c172p 'Out of fuel!' messages while flying: {dry}"
                        + (" ok" if dry == 0 else " MISMATCH"))
                    ok &= dry == 0
                    ok &= negative_checks(args, fg, results)
                    if not args.no_direct:
                        direct_run(args, fg, results)
            finally:
                fg.stop()
    finally:
        stop(xvfb)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    log("\nALL CHECKS PASSED" if ok else "\nSOME CHECKS FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (RuntimeError, OSError, ValueError) as e:
        print(f"flightgear_check: {e}", file=sys.stderr)
        sys.exit(1)
